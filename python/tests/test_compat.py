"""panoproj.compat against py360convert 1.0.4 on the Jordan Pond panorama: the same shapes,
dtypes, formats and orientations; PSNR reported (pytest -s prints them). The geometry agrees to
50+ dB once py360convert's sample positions are given to the engine (its face pixels span the
face edge to edge: pinhole faces of fov 2 atan(w / (w - 1))), so what remains is those half-pixel
positions and antialiasing."""

import math
import pathlib

import numpy as np
import pytest

import panoproj as pp
from panoproj import compat

py360convert = pytest.importorskip("py360convert")
ROOT = pathlib.Path(__file__).resolve().parents[2]
PANO = pp.read(str(ROOT / "samples/images/jordan_pond_4096x2048.jpg"))
FACES = [pp.read(str(p)) for p in sorted((ROOT / "samples/images/cubemap_jordan_pond").glob("face*.jpg"))]


def psnr(a, b):
    d = a.astype(np.float64) - b.astype(np.float64)
    return 10 * math.log10(255.0**2 / np.mean(d * d))


def _same(a, b):
    assert type(a) is type(b)
    if isinstance(a, dict):
        assert list(a) == list(b)
        return [_same(a[k], b[k]) for k in a]
    if isinstance(a, list):
        assert len(a) == len(b)
        return [_same(x, y) for x, y in zip(a, b)]
    assert a.shape == b.shape and a.dtype == b.dtype
    return psnr(a, b)


@pytest.mark.parametrize("fmt", ["horizon", "dice", "list", "dict"])
def test_e2c_in_every_format(fmt):
    ours, theirs = compat.e2c(PANO, 1024, cube_format=fmt), py360convert.e2c(PANO, 1024, cube_format=fmt)
    scores = np.ravel(_same(ours, theirs))
    print(f"e2c {fmt}: PSNR {' '.join(f'{s:.1f}' for s in scores)} dB")
    assert min(scores) > 29


@pytest.mark.parametrize("fmt", ["horizon", "dice", "list", "dict"])
def test_c2e_from_every_format(fmt):
    cube = {"list": FACES, "dict": dict(zip("FRBLUD", FACES)), "horizon": py360convert.cube_list2h(FACES)}.get(
        fmt) if fmt != "dice" else py360convert.cube_h2dice(py360convert.cube_list2h(FACES))
    ours, theirs = compat.c2e(cube, 2048, 4096, cube_format=fmt), py360convert.c2e(cube, 2048, 4096, cube_format=fmt)
    score = _same(ours, theirs)
    print(f"c2e {fmt}: PSNR {score:.1f} dB")
    assert score > 25


@pytest.mark.parametrize("u,v,rot", [(0, 0, 0), (120, 23, 0), (-60, -40, 30), (170, 60, -45), (0, -90, 0),
                                     (0, 90, 10)])
def test_e2p_with_rotations(u, v, rot):
    ours = compat.e2p(PANO, (90, 70), u, v, (480, 640), rot)
    theirs = py360convert.e2p(PANO, (90, 70), u, v, (480, 640), rot)
    score = _same(ours, theirs)
    print(f"e2p u={u} v={v} rot={rot}: PSNR {score:.1f} dB")
    assert score > 25
    if rot:  # the deliberate mistake: the in-plane turn the other way
        assert psnr(compat.e2p(PANO, (90, 70), u, v, (480, 640), -rot), theirs) < score - 10


@pytest.mark.parametrize("face,yaw,pitch", [(0, 0, 0), (1, 90, 0), (2, 180, 0), (3, -90, 0), (4, 0, 90), (5, 0, -90)])
def test_orientation_agrees_at_their_sample_positions(face, yaw, pitch):
    w = 256
    theirs = py360convert.cube_h2list(py360convert.e2c(PANO, w, cube_format="horizon"))[face]
    fov = 2 * math.degrees(math.atan(w / (w - 1)))
    ours = pp.convert(PANO, "equirect", pp.Pinhole(hfov=fov), size=(w, w), yaw=yaw, pitch=pitch, interp="bilinear",
                      antialias="off")
    assert psnr(ours, theirs) > 50


def test_cube_helpers_agree_and_round_trip():
    h = py360convert.cube_list2h(FACES)
    dice = compat.cube_h2dice(h)
    np.testing.assert_array_equal(dice, py360convert.cube_h2dice(h))
    np.testing.assert_array_equal(compat.cube_dice2h(dice), h)
    np.testing.assert_array_equal(compat.cube_list2h(compat.cube_h2list(h)), h)
    np.testing.assert_array_equal(compat.cube_dict2h(compat.cube_h2dict(h)), h)
    assert list(compat.cube_h2dict(h)) == list(py360convert.cube_h2dict(h))
    np.testing.assert_array_equal(compat.cube_dict2h({k.lower(): v for k, v in compat.cube_h2dict(h).items()},
                                                     face_k="frblud"), h)


@pytest.mark.parametrize("call,cls,text", [
    (lambda: compat.e2c(PANO, 8, mode="biquintic"), ValueError, "mode: 'biquintic' (a spline order panoproj does "
                                                               "not have; expected 'nearest', 'bilinear'"),
    (lambda: compat.e2c(PANO, 8, cube_format="cross"), ValueError, "cube_format: 'cross' (expected 'horizon'"),
    (lambda: compat.c2e(FACES[0], 8, 16, cube_format="list"), TypeError, "expected a list of six faces"),
    (lambda: compat.cube_h2list(FACES[0]), ValueError, "cube_h: shape (1584, 1584, 3) (expected w x 6w"),
    (lambda: compat.cube_list2h(FACES[:5]), ValueError, "cube_list: 5 faces"),
    (lambda: compat.cube_dict2h({"F": FACES[0]}), KeyError, "cube_dict: no face 'R'"),
])
def test_bad_inputs(call, cls, text):
    with pytest.raises(cls) as e:
        call()
    assert text in str(e.value) and "\n" not in str(e.value), str(e.value)


def test_py360convert_readme_example_runs_with_the_import_changed():
    py = compat  # "import py360convert" -> "from panoproj import compat as py360convert"
    cube_dice = py.cube_h2dice(py.e2c(PANO, 256, cube_format="horizon"))  # their demo_cube.png's shape
    cube_h = py.cube_dice2h(cube_dice)  # the inverse is cube_h2dice
    cube_dict = py.cube_h2dict(cube_h)  # the inverse is cube_dict2h
    cube_list = py.cube_h2list(cube_h)  # the inverse is cube_list2h
    assert cube_dice.shape == (768, 1024, 3) and cube_h.shape == (256, 1536, 3)
    assert list(cube_dict.keys()) == ["F", "R", "B", "L", "U", "D"] and cube_dict["F"].shape == (256, 256, 3)
    assert len(cube_list) == 6 and cube_list[0].shape == (256, 256, 3)
    assert py.c2e(cube_dice, 400, 800).shape == (400, 800, 3)  # convert360 c2e ... --width 800 --height 400
    assert py.e2p(PANO, 90, 120, 23, (300, 300)).shape == (300, 300, 3)  # convert360 e2p ... --yaw 120 --pitch 23
