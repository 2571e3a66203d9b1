"""Bad input raises a clear exception (the command's one-line message); nothing crashes and no
output file is left behind."""
import math
import os

import numpy as np
import pytest

import panoproj as pp
from conftest import smooth_equirect

IMG = smooth_equirect(128, 64)


@pytest.mark.parametrize("dtype,what", [
    (np.complex64, r"array dtype complex64 \(expected uint8, uint16, float16, float32 or float64; any integer or "
                   r"bool with interp='nearest'\)"),
    (np.int32, "array dtype int32: integers other than uint8/uint16 and bool are labels, copied exactly by "
               "interp='nearest'"),
    (np.int8, "array dtype int8: .*interp='nearest'"), (np.bool_, "array dtype bool: .*interp='nearest'"),
    (np.uint64, "array dtype uint64: .*interp='nearest'"), ("datetime64[s]", "array dtype datetime64"),
    (object, "array dtype object")])
def test_wrong_dtype_is_a_type_error(dtype, what):
    with pytest.raises(TypeError, match=what):
        pp.convert(IMG.astype(dtype), "equirect", "pinhole")


@pytest.mark.parametrize("shape,what", [((64, 128, 0), r"\(64, 128, 0\): empty"),
                                        ((0, 128, 3), r"\(0, 128, 3\): empty"),
                                        ((2, 4, 64, 128, 3), "5 dimensions"), ((128,), "1 dimensions")])
def test_wrong_shapes_are_value_errors(shape, what):
    with pytest.raises(ValueError, match=what):
        pp.convert(np.zeros(shape, np.uint8), "equirect", "pinhole")


@pytest.mark.parametrize("kw,what", [
    (dict(yaw=math.nan), "yaw: nan"), (dict(pitch=math.inf), "pitch: inf"), (dict(roll=-math.inf), "roll: -inf"),
    (dict(size=(0, 10)), "size: 0x10"), (dict(size=(10, -1)), "size: 10x-1"), (dict(size="10y10"), "size: '10y10'"),
    (dict(threads=-1), "threads: -1"), (dict(interp="cubic"), "cubic"), (dict(engine="gpu"), "gpu"),
])
def test_bad_options_are_value_errors(kw, what):
    with pytest.raises(ValueError, match=what):
        pp.convert(IMG, "equirect", "pinhole", **kw)


@pytest.mark.parametrize("spec,what", [
    ("robinson", "robinson"), ("fisheye:fov=400", "fov"), ("fisheye:fov=nan", "fov"), ("pinhole:hfov=180", "hfov"),
    ("fisheye:model=fancy", "fancy"), ("equirect:tilt=3", "tilt"),
])
def test_bad_specs_are_value_errors(spec, what):
    with pytest.raises(ValueError, match=what):
        pp.convert(IMG, "equirect", spec)
    with pytest.raises(ValueError, match=what):
        pp.projection(spec)


def test_keyword_constructors_check_names_and_ranges():
    with pytest.raises(TypeError, match="unexpected keyword argument 'fv'"):
        pp.Fisheye(fv=180)
    with pytest.raises(ValueError, match="fov"):
        pp.Fisheye(fov=-1)
    with pytest.raises(ValueError, match="fov"):
        pp.Fisheye(fov=math.inf)


def test_source_of_the_wrong_size_is_a_value_error():
    with pytest.raises(ValueError, match=r"src: None, and a 128x65 image is not a 2:1 equirect"):
        pp.convert(np.zeros((65, 128, 3), np.uint8), None, "pinhole")
    plan = pp.Plan("equirect", "pinhole", (256, 128))
    with pytest.raises(ValueError, match="image size 128x64 does not match the source projection's 256x128"):
        plan(IMG)
    with pytest.raises(ValueError, match="out: expected"):
        plan(smooth_equirect(256, 128), out=np.zeros((3, 3, 3), np.uint8))


def test_mismatched_cube_faces_are_value_errors():
    faces = [np.zeros((32, 32, 3), np.uint8) for _ in range(6)]
    faces[4] = np.zeros((32, 32, 4), np.uint8)
    with pytest.raises(ValueError, match="cube face up: 32x32x4 uint8 differs from the front face's 32x32x3 uint8"):
        pp.convert(faces, "cubemap", "equirect")
    faces[4] = np.zeros((32, 32, 3), np.uint16)
    with pytest.raises(ValueError, match="cube face up: .* uint16 differs"):
        pp.convert(faces, "cubemap", "equirect")
    with pytest.raises(ValueError, match="cube face front: 32x31"):
        pp.convert([np.zeros((31, 32, 3), np.uint8)] * 6, "cubemap", "equirect")
    with pytest.raises(ValueError, match="cube faces: 5 arrays"):
        pp.convert([np.zeros((32, 32, 3), np.uint8)] * 5, "cubemap", "equirect")
    with pytest.raises(ValueError, match="expected cubemap, layout 6x1 or files"):
        pp.convert([np.zeros((32, 32, 3), np.uint8)] * 6, "cubemap:layout=cross", "equirect")


def test_file_errors_are_os_errors_and_leave_nothing(tmp_path):
    with pytest.raises(OSError, match="does not exist"):
        pp.read(str(tmp_path / "missing.jpg"))
    bad = tmp_path / "bad.jpg"
    bad.write_bytes(b"not a jpeg")
    with pytest.raises(OSError, match="cannot read"):
        pp.read(str(bad))
    target = tmp_path / "out.png"
    target.write_bytes(b"keep me")
    with pytest.raises(OSError, match="exists"):
        pp.write(str(target), IMG)
    assert target.read_bytes() == b"keep me"
    with pytest.raises(OSError, match="no image format"):
        pp.write(str(tmp_path / "out.xyz"), IMG)
    assert sorted(os.listdir(tmp_path)) == ["bad.jpg", "out.png"]


def test_bad_rays_and_positions_give_ok_false_not_errors():
    rays = np.array([[0, 0, 0], [math.nan, 0, 1], [0, 0, 1]], float)
    x, y, ok = pp.to_pixel("equirect", (64, 32), rays)
    assert ok.tolist() == [False, False, True] and math.isnan(x[0]) and x[2] == 32
    r, ok = pp.to_ray("pinhole", (64, 64), np.array([math.inf, 32.0]), np.array([1.0, 32.0]))
    assert ok.tolist() == [False, True] and np.isnan(r[0]).all()
    with pytest.raises(ValueError, match="last dimension 2"):
        pp.to_pixel("equirect", (64, 32), np.zeros((4, 2)))
