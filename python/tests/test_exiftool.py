"""The Photo Sphere XMP panoproj writes (JPEG and PNG), read back by a second, independent reader: exiftool
(installed by scripts/test.sh; OpenImageIO drops the GPano namespace, so panoproj's own reader is
the other one, in ctest). A partial equirect's crop fields are where its spec puts it."""
import json
import shutil
import subprocess

import pytest


@pytest.mark.skipif(shutil.which("exiftool") is None, reason="exiftool is not installed (scripts/test.sh installs it)")
@pytest.mark.parametrize("ext", ["jpg", "png"])
@pytest.mark.parametrize("spec,size,expected", [
    ("equirect", "1024x512", dict(FullPanoWidthPixels=1024, FullPanoHeightPixels=512, CroppedAreaImageWidthPixels=1024,
                                  CroppedAreaImageHeightPixels=512, CroppedAreaLeftPixels=0, CroppedAreaTopPixels=0)),
    # hfov 180 of 800 px: a 1600-px panorama; centre lon 60 -> x 1066.7, left 666.7; top lat 55 -> y 155.6.
    ("equirect:hfov=180,vfov=90,lon0=60,lat0=10", "800x400",
     dict(FullPanoWidthPixels=1600, FullPanoHeightPixels=800, CroppedAreaImageWidthPixels=800,
          CroppedAreaImageHeightPixels=400, CroppedAreaLeftPixels=667, CroppedAreaTopPixels=156)),
])
def test_exiftool_reads_the_photo_sphere_fields(cli, pond, tmp_path, ext, spec, size, expected):
    out = tmp_path / f"pano.{ext}"
    subprocess.run([cli, "convert", pond, str(out), "--to", spec, "--size", size, "-q"], check=True)
    tags = json.loads(subprocess.run(["exiftool", "-j", "-n", "-XMP-GPano:all", str(out)], check=True,
                                     capture_output=True, text=True).stdout)[0]
    assert tags["ProjectionType"] == "equirectangular"
    assert tags["UsePanoramaViewer"] in (True, 1, "True")
    for key, value in expected.items():
        assert tags[key] == value, key
