"""Stereo frames from Python: stereo=tb|sbs equals the two mono conversions stacked, bit for bit,
through convert, Plan.run(out=), batches, typed projections and eye=; the classes' errors."""
import numpy as np
import pytest

import panoproj as pp

RNG = np.random.default_rng(21)
EYE_W, EYE_H = 128, 64


def stereo_equirect(layout: str):
    left = RNG.integers(0, 256, (EYE_H, EYE_W, 3), np.uint8)
    right = RNG.integers(0, 256, (EYE_H, EYE_W, 3), np.uint8)
    return left, right, np.concatenate([left, right], axis=0 if layout == "tb" else 1)


def stack(a, b, layout):
    return np.concatenate([a, b], axis=0 if layout == "tb" else 1)


@pytest.mark.parametrize("src_layout", ["tb", "sbs"])
@pytest.mark.parametrize("dst_layout", ["tb", "sbs"])
@pytest.mark.parametrize("interp", ["nearest", "bicubic"])
def test_stereo_is_two_mono_conversions(src_layout, dst_layout, interp):
    left, right, frame = stereo_equirect(src_layout)
    eye = (96, 96)
    size = (eye[0], 2 * eye[1]) if dst_layout == "tb" else (2 * eye[0], eye[1])
    kw = dict(interp=interp, antialias="off" if interp == "nearest" else "auto")
    got = pp.convert(frame, f"equirect:stereo={src_layout}", f"fisheye:fov=180,stereo={dst_layout}", size=size, **kw)
    want = stack(pp.convert(left, "equirect", "fisheye:fov=180", size=eye, **kw),
                 pp.convert(right, "equirect", "fisheye:fov=180", size=eye, **kw), dst_layout)
    assert got.shape == want.shape and np.array_equal(got, want)


def test_plan_run_out_and_batches():
    left, right, frame = stereo_equirect("tb")
    size = (3 * 32, 2 * 2 * 32)  # eac eyes of 96x64, stacked
    plan = pp.Plan("equirect:stereo=tb", "cubemap:layout=eac,stereo=tb", (EYE_W, 2 * EYE_H), size=size,
                   interp="bilinear")
    out = np.empty((size[1], size[0], 3), np.uint8)
    plan.run(frame, out=out)
    want = stack(pp.convert(left, "equirect", "cubemap:layout=eac", size=(96, 64), interp="bilinear"),
                 pp.convert(right, "equirect", "cubemap:layout=eac", size=(96, 64), interp="bilinear"), "tb")
    assert np.array_equal(out, want)
    batch = plan(np.stack([frame, frame[::-1].copy()]))
    assert np.array_equal(batch[0], want)
    assert np.array_equal(batch[1], pp.convert(frame[::-1].copy(), "equirect:stereo=tb",
                                               "cubemap:layout=eac,stereo=tb", size=size, interp="bilinear"))


def test_eye_and_mono_to_stereo():
    left, right, frame = stereo_equirect("sbs")
    kw = dict(size=(160, 90), interp="lanczos3")
    assert np.array_equal(pp.convert(frame, "equirect:stereo=sbs,eye=right", "pinhole:hfov=90", **kw),
                          pp.convert(right, "equirect", "pinhole:hfov=90", **kw))
    assert np.array_equal(pp.convert(frame, "equirect:stereo=sbs", "pinhole:hfov=90", **kw),
                          pp.convert(left, "equirect", "pinhole:hfov=90", **kw))
    both = pp.convert(left, "equirect", "pinhole:hfov=90,stereo=tb", size=(160, 180), interp="lanczos3")
    one = pp.convert(left, "equirect", "pinhole:hfov=90", **kw)
    assert np.array_equal(both, stack(one, one, "tb"))


def test_typed_projections_take_stereo():
    left, right, frame = stereo_equirect("tb")
    src = pp.Equirect(stereo="tb", eye="right")
    assert "stereo=tb" in str(src) and "eye=right" in str(src)
    assert np.array_equal(pp.convert(frame, src, pp.Fisheye(fov=180), size=(64, 64)),
                          pp.convert(right, "equirect", "fisheye:fov=180", size=(64, 64)))


@pytest.mark.parametrize("src, dst, size, words", [
    ("equirect:stereo=tb", "fisheye:stereo=tb", (64, 65), "does not split into two eyes"),
    ("equirect:eye=left", "fisheye", (64, 64), "eye=left picks an eye of a stereo source"),
    ("equirect", "fisheye:eye=left", (64, 64), "eye= is for the source"),
    ("equirect:stereo=lr", "fisheye", (64, 64), "stereo=lr is not a valid value"),
])
def test_stereo_errors(src, dst, size, words):
    with pytest.raises(ValueError, match=words):
        pp.convert(np.zeros((EYE_H * 2, EYE_W, 3), np.uint8), src, dst, size=size)


def test_build_map_refuses_stereo():
    with pytest.raises(ValueError, match="stereo"):
        pp.build_map("equirect:stereo=tb", "fisheye", (EYE_W, 2 * EYE_H), size=(64, 64))
