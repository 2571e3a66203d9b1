"""The module and the command give the same bytes for the same conversion."""
import subprocess

import numpy as np
import pytest

import panoproj as pp

CASES = [
    ("cubemap:face=256", []),
    ("pinhole:hfov=100", ["--yaw", "30", "--pitch", "-20", "--roll", "5", "--size", "640x480"]),
    ("fisheye:fov=200,model=equisolid", ["--pitch", "90", "--size", "512x512", "--interp", "lanczos3"]),
    ("aitoff", ["--size", "512x256", "--interp", "bilinear"]),
]


def options(args):
    """The command's options as convert() keywords."""
    kw = {}
    for flag, value in zip(args[::2], args[1::2]):
        key = flag.lstrip("-")
        kw[key] = value if key == "interp" else (value if key == "size" else float(value))
    return kw


@pytest.mark.parametrize("dst,args", CASES, ids=[c[0] for c in CASES])
def test_equirect_photo_matches_the_command_bit_for_bit(tmp_path, cli, pond, dst, args):
    out = tmp_path / "cli.png"
    subprocess.run([cli, "convert", pond, str(out), "--to", dst, "-q", *args], check=True)
    ours = pp.convert(pp.read(pond), None, dst, **options(args))
    theirs = pp.read(str(out))
    assert ours.shape == theirs.shape and ours.dtype == theirs.dtype
    assert np.array_equal(ours, theirs)


def test_cube_face_files_match_the_command_bit_for_bit(tmp_path, cli, pond_faces):
    out = tmp_path / "cli.png"
    subprocess.run([cli, "convert", pond_faces, str(out), "--to", "equirect", "--size", "1024x512", "-q"],
                   check=True)
    faces = pp.split_faces(pp.read(pond_faces))
    ours = pp.convert(faces, "cubemap:layout=files", "equirect", size=(1024, 512))
    assert np.array_equal(ours, pp.read(str(out)))
