"""The three ways the module reaches files beyond JPEG, PNG and PPM, each in a fresh interpreter:
"plugin" (the system's OpenImageIO 2.4 through libpanoproj_oiio.so), "package" (the `openimageio`
Python package, 3.x, where the plugin is missing) and "none" (neither: JPEG, PNG and PPM alone,
with the built-in metadata set). The plugin is the oracle for the other two."""
import ast
import functools
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

import panoproj as pp
from conftest import HUGE_HDR, SAMPLES, huge_exr, huge_tiff, smooth_equirect

try:
    import OpenImageIO  # noqa: F401
    HAVE_PACKAGE = True
except ImportError:
    HAVE_PACKAGE = False

needs_package = pytest.mark.skipif(not HAVE_PACKAGE, reason="the openimageio package is not installed (pip install openimageio)")
HIDE_PACKAGE = "import sys; sys.modules['OpenImageIO'] = None\n"  # (an import of it raises ImportError)
PRELUDE = {"plugin": HIDE_PACKAGE, "package": "", "none": HIDE_PACKAGE}


def run_in(mode, code):
    """Runs code (which prints a Python literal) with the module on the given path; returns the value."""
    env = dict(os.environ)
    if mode != "plugin":
        env["PANOPROJ_OIIO_PLUGIN"] = "/nonexistent/libpanoproj_oiio.so"
    p = subprocess.run([sys.executable, "-c", PRELUDE[mode] + "import numpy as np, panoproj as pp\n" + code],
                       capture_output=True, text=True, env=env, timeout=120)
    assert p.returncode == 0, p.stderr
    return ast.literal_eval(p.stdout.strip().splitlines()[-1])


def metadata_in(mode, path):
    return run_in(mode, f"print(repr(pp.read({str(path)!r}, metadata=True)[1]))")


@functools.lru_cache(None)
def plugin_works():
    """Whether the system's OpenImageIO is there through the plugin (an EXR read without the package)."""
    try:
        return run_in("plugin", f"print(pp.read({str(SAMPLES / 'blender_city_1024x512.exr')!r}).shape)") is not None
    except AssertionError:
        return False


@pytest.fixture(scope="module")
def tagged(tmp_path_factory):
    """A JPEG and a PNG with EXIF (IFD0, Exif and GPS tags of every value type), an ICC profile and
    GPano fields, written by exiftool (an independent writer)."""
    if shutil.which("exiftool") is None:
        pytest.skip("exiftool is not installed (scripts/test.sh installs it)")
    d = tmp_path_factory.mktemp("tagged")
    icc = SAMPLES.parent / "icc" / "srgb_lcms2.icc"
    out = {}
    for ext in ("jpg", "png"):
        path = d / f"tagged.{ext}"
        pp.write(str(path), smooth_equirect(128, 64))
        subprocess.run(["exiftool", "-q", "-overwrite_original", "-EXIF:Make=Ricoh", "-EXIF:Model=THETA Z1",
                        "-EXIF:Software=test", "-EXIF:Artist=me", "-EXIF:Copyright=cc", "-EXIF:ImageDescription=desc",
                        "-EXIF:ModifyDate=2024:05:01 10:11:12", "-EXIF:DateTimeOriginal=2024:05:01 10:11:12",
                        "-EXIF:CreateDate=2024:05:01 10:11:13", "-EXIF:FNumber=2.8", "-EXIF:ExposureTime=0.004",
                        "-EXIF:FocalLength=2.57", "-EXIF:ISO=100", "-EXIF:Orientation#=6", "-EXIF:XResolution=300",
                        "-EXIF:YResolution=300", "-EXIF:ResolutionUnit=cm", "-EXIF:ExposureProgram#=2",
                        "-EXIF:MeteringMode#=5", "-EXIF:ExposureCompensation=-0.7", "-EXIF:FocalLengthIn35mmFormat=14",
                        "-EXIF:LensModel=lens", "-EXIF:LensMake=lmake", "-EXIF:SerialNumber=SN1", "-EXIF:ColorSpace#=1",
                        "-EXIF:ExifImageWidth=128", "-EXIF:ExifImageHeight=64", "-GPSLatitude=44.35",
                        "-GPSLatitudeRef=N", "-GPSLongitude=68.2", "-GPSLongitudeRef=W", "-GPSAltitude=12.5",
                        "-GPSAltitudeRef#=0", "-XMP-GPano:ProjectionType=equirectangular",
                        "-XMP-GPano:UsePanoramaViewer=True", "-XMP-GPano:PoseHeadingDegrees=90",
                        "-XMP-GPano:PosePitchDegrees=1.5", "-XMP-GPano:FullPanoWidthPixels=128",
                        "-XMP-GPano:FullPanoHeightPixels=64", "-XMP-GPano:InitialViewHeadingDegrees=10",
                        f"-ICC_Profile<={icc}", str(path)], check=True)
        out[ext] = path
    return out


# Keys the paths give differently, and why (everything else must be equal): OpenImageIO's PNG
# reader leaves EXIF's ResolutionUnit a number, its JPEG reader takes the unit of the JFIF header
# over EXIF's; the built-in set gives EXIF's as "in", "cm" or "none" (checked against exiftool's
# value below).
PLUGIN_DIFFERS = {("png", "ResolutionUnit"), ("jpg", "ResolutionUnit")}


@pytest.mark.parametrize("ext", ["jpg", "png"])
def test_built_in_metadata_equals_openimageios(tagged, ext):
    """Without OpenImageIO: a subset of the plugin's keys, with equal values, holding the tags
    written (a deliberate mistake in a rational's sign or a name fails here)."""
    if not plugin_works():
        pytest.skip("no OpenImageIO plugin here")
    lean, full = metadata_in("none", tagged[ext]), metadata_in("plugin", tagged[ext])
    for key, value in lean.items():
        if (ext, key) not in PLUGIN_DIFFERS:
            assert full.get(key, "missing") == value, key
    expected = {"Make": "Ricoh", "Model": "THETA Z1", "Orientation": 6, "ResolutionUnit": "cm",
                "ExposureTime": float(np.float32(0.004)), "FNumber": float(np.float32(2.8)),
                "Exif:ExposureBiasValue": float(np.float32(-0.7)), "Exif:PhotographicSensitivity": 100,
                "Exif:DateTimeOriginal": "2024:05:01 10:11:12", "Exif:ExifVersion": "0232",
                "GPS:LatitudeRef": "N", "GPS:Altitude": 12.5, "GPano:ProjectionType": "equirectangular",
                "GPano:UsePanoramaViewer": 1, "GPano:PoseHeadingDegrees": 90.0, "GPano:InitialViewHeadingDegrees": 10,
                "GPano:FullPanoWidthPixels": 128}
    assert {k: lean.get(k) for k in expected} == expected
    assert lean["GPS:Latitude"][0] == 44 and abs(lean["GPS:Latitude"][1] + lean["GPS:Latitude"][2] / 60 - 21) < 1e-9
    assert lean["ICCProfile"] == (SAMPLES.parent / "icc" / "srgb_lcms2.icc").read_bytes()


@needs_package
@pytest.mark.parametrize("ext", ["jpg", "png"])
def test_package_metadata_holds_the_built_in_set(tagged, ext):
    """The package (OpenImageIO 3.x) gives every built-in key with the same value."""
    lean, package = metadata_in("none", tagged[ext]), metadata_in("package", tagged[ext])
    for key, value in lean.items():
        if (ext, key) not in PLUGIN_DIFFERS:
            assert package.get(key, "missing") == value, key
    # An integer array (int[4]) as stored: the plugin once gave zeros past its first element.
    assert package["GPS:VersionID"] == (2.0, 3.0, 0.0, 0.0)
    if plugin_works():
        assert metadata_in("plugin", tagged[ext])["GPS:VersionID"] == package["GPS:VersionID"]


@pytest.mark.parametrize("mode", ["plugin", "package", "none"])
def test_gpano_as_panoproj_writes_it_is_read_on_every_path(cli, pond, tmp_path, mode):
    """A partial equirect's Photo Sphere fields (which OpenImageIO does not decode as panoproj lays
    them out) come back on every path, as the spec placed them."""
    if mode == "package" and not HAVE_PACKAGE:
        pytest.skip("no openimageio package")
    if mode == "plugin" and not plugin_works():
        pytest.skip("no OpenImageIO plugin here")
    out = tmp_path / "partial.jpg"
    subprocess.run([cli, "convert", pond, str(out), "--to", "equirect:hfov=180,vfov=90,lon0=60,lat0=10", "--size",
                    "800x400", "-q"], check=True)
    md = metadata_in(mode, out)
    assert {k: md.get(f"GPano:{k}") for k in ("FullPanoWidthPixels", "CroppedAreaLeftPixels", "CroppedAreaTopPixels")} \
        == {"FullPanoWidthPixels": 1600, "CroppedAreaLeftPixels": 667, "CroppedAreaTopPixels": 156}


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """TIFF (8 and 16 bits), EXR (half and float, RGBA) and HDR files written through the plugin."""
    d = tmp_path_factory.mktemp("written")
    rng = np.random.default_rng(7)
    cases = {"u8.tif": (rng.integers(0, 256, (24, 48, 3)), np.uint8),
             "u16.tif": (rng.integers(0, 65536, (24, 48, 1)), np.uint16),
             "half.exr": (rng.random((24, 48, 4)), np.float16), "float.exr": (rng.random((24, 48, 3)), np.float32),
             "x.hdr": (rng.random((24, 48, 3)), np.float32)}
    for name, (a, dt) in cases.items():
        pp.write(str(d / name), a.astype(dt).squeeze(), metadata={"ImageDescription": "panoproj", "Artist": "a"})
    return d, sorted(cases)


@needs_package
def test_package_reads_what_the_plugin_reads(written):
    if not plugin_works():
        pytest.skip("no OpenImageIO plugin here")
    d, names = written
    paths = [str(d / n) for n in names] + [str(SAMPLES / "blender_city_1024x512.exr")]
    code = f"print(repr([(a.dtype.str, a.shape, a.tobytes().hex()) for a in map(pp.read, {paths!r})]))"
    assert run_in("package", code) == run_in("plugin", code)
    for p in paths[:-1]:
        md = metadata_in("package", p)
        if not p.endswith(".hdr"):  # (Radiance HDR has no place for these)
            assert md.get("ImageDescription") == "panoproj" and md.get("Artist") == "a", p


@needs_package
@pytest.mark.parametrize("name", ["u8.tif", "u16.tif", "half.exr", "float.exr", "x.hdr", "{face}.exr"])
def test_package_writes_what_the_plugin_reads(written, tmp_path, name):
    """Written through the package (atomically, with attributes), read back by the plugin: equal
    samples (HDR: its 8-bit mantissas), six face files too."""
    d, _ = written
    src = d / (name if "{" not in name else "float.exr")
    out = tmp_path / name
    face = "{" in name
    code = (f"a = pp.read({str(src)!r})\n" + ("a = np.concatenate([a[:, :24]] * 6, axis=1)\n" if face else "") +
            f"pp.write({str(out)!r}, a, metadata={{'Artist': 'b', 'panoproj:v': (1.0, 2.5)}})\nprint(1)")
    run_in("package", code)
    a = pp.read(str(src))
    if face:
        a = np.concatenate([a[:, :24]] * 6, axis=1)
    back = pp.read(str(out))
    assert back.dtype == a.dtype and back.shape == a.shape
    if name.endswith(".hdr"):
        assert np.allclose(back, a, rtol=2 ** -7, atol=1e-6)
    else:
        assert np.array_equal(back, a)
    assert sorted(p.name for p in tmp_path.iterdir()) == (
        sorted(f"{f}.exr" for f in ("front", "right", "back", "left", "up", "down")) if face else [name])
    if not face and not name.endswith(".hdr"):
        md = pp.read(str(out), metadata=True)[1]
        assert md.get("Artist") == "b"
        if name.endswith(".exr"):  # (a tuple: the type the package needs spelled out)
            assert md.get("panoproj:v") == (1.0, 2.5)


@needs_package
def test_package_writes_are_atomic_and_refusals_are_one_line(written, tmp_path):
    d, _ = written
    a = pp.read(str(d / "float.exr"))
    old = tmp_path / "old.exr"
    old.write_bytes(b"old")
    code = (f"a = np.zeros((8, 8, 3), np.float32)\n"
            f"out = []\n"
            f"for call in (lambda: pp.write({str(old)!r}, a), lambda: pp.write({str(tmp_path / 'no' / 'x.exr')!r}, a),\n"
            f"             lambda: pp.read({str(tmp_path / 'missing.exr')!r})):\n"
            f"    try:\n        call(); out.append('written')\n"
            f"    except OSError as e:\n        out.append((type(e).__name__, str(e)))\n"
            f"print(repr(out))")
    results = run_in("package", code)
    assert results[0][0] == "FileExistsError" and "overwrite=True" in results[0][1]
    assert results[1][0] in ("FileNotFoundError", "OSError") and "does not exist" in results[1][1]
    assert results[2][0] == "FileNotFoundError"
    assert all("\n" not in r[1] for r in results)
    assert old.read_bytes() == b"old" and sorted(p.name for p in tmp_path.iterdir()) == ["old.exr"]
    assert a.shape == (24, 48, 3)


@needs_package
@pytest.mark.parametrize("kind", ["huge", "cut"])
@pytest.mark.parametrize("ext", ["tif", "exr", "hdr"])
def test_package_refuses_hostile_files_in_one_line(written, tmp_path, kind, ext):
    """A header declaring a gigapixel image in a small file, and a file cut in half: OSError or
    MemoryError in one line naming the file, before any large allocation."""
    d, _ = written
    src = d / {"tif": "u8.tif", "exr": "float.exr", "hdr": "x.hdr"}[ext]
    data = src.read_bytes()
    bad = tmp_path / f"bad.{ext}"
    if kind == "cut":
        bad.write_bytes(data[:len(data) // 2])
    else:
        bad.write_bytes({"tif": huge_tiff, "exr": lambda: huge_exr(data), "hdr": lambda: HUGE_HDR}[ext]())
    # (Peak memory from VmHWM: getrusage's maxrss keeps the forking pytest's across exec.)
    code = (f"try:\n    pp.read({str(bad)!r})\n    r = 'read'\n"
            f"except (OSError, MemoryError, ValueError) as e:\n    r = (type(e).__name__, str(e))\n"
            f"hwm = [l for l in open('/proc/self/status') if l.startswith('VmHWM')][0].split()[1]\n"
            f"print(repr((r, int(hwm) // 1024)))")
    (kind_, message), rss_mb = run_in("package", code)
    assert kind_ in ("OSError", "MemoryError") and str(bad) in message and "\n" not in message, message
    assert rss_mb < 300


def test_without_openimageio_other_formats_name_both_installs(written):
    d, _ = written
    code = (f"try:\n    pp.read({str(d / 'float.exr')!r}); r = 'read'\n"
            f"except OSError as e:\n    r = str(e)\nprint(repr(r))")
    message = run_in("none", code)
    assert "pip install openimageio" in message and "apt install libopenimageio2.4" in message, message
    assert "\n" not in message and "float.exr" in message
    # JPEG and PNG, their metadata included, need neither.
    assert run_in("none", f"print(pp.read({str(SAMPLES / 'jordan_pond_4096x2048.jpg')!r}, metadata=True)[0].shape)") \
        == (2048, 4096, 3)


@needs_package
@pytest.mark.parametrize("ext", ["jpg", "png"])
def test_package_writes_exif_attributes_into_jpeg_and_png(tmp_path, ext):
    """EXIF attributes by name need OpenImageIO's EXIF encoder: through the package here, read back
    by the built-in reader (neither OpenImageIO) and by the plugin where it is there."""
    out = tmp_path / f"x.{ext}"
    run_in("package", f"pp.write({str(out)!r}, np.full((16, 32, 3), 7, np.uint8), "
                      f"metadata={{'Artist': 'someone', 'Make': 'Acme', 'Orientation': 1}})\nprint(1)")
    md = metadata_in("none", out)
    assert (md.get("Artist"), md.get("Make"), md.get("Orientation")) == ("someone", "Acme", 1)
    assert np.array_equal(pp.read(str(out)), np.full((16, 32, 3), 7, np.uint8)) or ext == "jpg"
    message = run_in("none", f"try:\n    pp.write({str(tmp_path / ('y.' + ext))!r}, np.zeros((8, 8, 3), np.uint8), "
                             f"metadata={{'Artist': 'a'}}); r = 'written'\nexcept OSError as e:\n    r = str(e)\nprint(repr(r))")
    assert "pip install openimageio" in message and not (tmp_path / f"y.{ext}").exists()
