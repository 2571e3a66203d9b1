"""Arrays as users hold them (panoproj/_arrays.py): dtypes, labels, batches, many channels,
other libraries' arrays, cube faces as lists and dicts; and the traps users fell into with them, each a test."""

import warnings

import numpy as np
import pytest

import panoproj as pp
from conftest import smooth_equirect

IMG = smooth_equirect(256, 128)  # uint8 HxWx3
rng = np.random.default_rng(19)


def _labels(shape=(256, 512), values=(0, 7, 300, 4000, 65535)):
    """Blobs of 5 labels (not noise: shrinking must have something to blend)."""
    y, x = np.mgrid[:shape[0], :shape[1]]
    index = ((x // 37 + y // 23) % len(values))
    return np.asarray(values, np.uint16)[index]


def test_nearest_keeps_a_label_mask_exact_when_shrinking_8x():
    mask = _labels()
    out = pp.convert(mask, "equirect", "pinhole:hfov=120", size=(64, 32), interp="nearest")
    assert set(np.unique(out)) == set(np.unique(mask)) and len(np.unique(out)) == 5
    # the deliberate mistake: antialiasing mixes labels into new values
    blended = pp.convert(mask.astype(np.float32), "equirect", "pinhole:hfov=120", size=(64, 32), interp="bilinear")
    assert len(np.unique(blended)) > 5


def test_nearest_refuses_antialiasing():
    with pytest.raises(ValueError, match="antialias='mip' with interp='nearest': nearest copies source pixels"):
        pp.convert(_labels(), "equirect", "pinhole", interp="nearest", antialias="mip")
    with pytest.raises(ValueError, match="antialias='4' with interp='nearest'"):
        pp.convert(_labels(), "equirect", "pinhole", interp="nearest", antialias=4)


@pytest.mark.parametrize("dtype", [np.int8, np.int16, np.int32, np.int64, np.uint32, np.uint64, np.float64, np.bool_,
                                   np.float16])
def test_labels_of_any_dtype_come_back_exactly(dtype):
    ids = _labels(values=(0, 1, 2, 3, 4))
    big = {np.int64: 2**40 + 1, np.uint64: 2**60 + 1, np.int32: -2**30 + 1, np.float64: 0.1}.get(dtype, 1)
    lut = (np.arange(5) * big).astype(dtype)  # labels whose bytes differ in every lane
    labels = lut[ids]
    out = pp.convert(labels, "equirect", "fisheye:fov=180", size=(96, 96), interp="nearest")
    assert out.dtype == labels.dtype and out.shape == (96, 96)
    # the same pixels as the uint16 ids take: each label's bytes travel together
    ref = pp.convert(ids, "equirect", "fisheye:fov=180", size=(96, 96), interp="nearest")
    np.testing.assert_array_equal(out, lut[ref])


def test_float64_goes_through_float32_and_comes_back_float64():
    unit = IMG / 255.0
    out = pp.convert(unit, "equirect", "pinhole", size=(64, 48))
    ref = pp.convert(unit.astype(np.float32), "equirect", "pinhole", size=(64, 48))
    assert out.dtype == np.float64
    np.testing.assert_array_equal(out, ref.astype(np.float64))


def test_interpolating_other_integers_is_refused_in_one_line():
    with pytest.raises(TypeError, match=r"array dtype int16: .*interp='nearest' \(or pass a.astype\(np.float32\)"):
        pp.convert(IMG.astype(np.int16), "equirect", "pinhole")


@pytest.mark.parametrize("channels", [5, 7, 12])
def test_more_than_4_channels_go_in_groups(channels):
    img = rng.random((128, 256, channels)).astype(np.float32)
    out = pp.convert(img, "equirect", "pinhole:hfov=100", size=(40, 30), interp="bicubic")
    assert out.shape == (30, 40, channels)
    for c in range(channels):  # each channel as it comes out alone
        alone = pp.convert(np.ascontiguousarray(img[..., c]), "equirect", "pinhole:hfov=100", size=(40, 30))
        np.testing.assert_allclose(out[..., c], alone, atol=2e-6)


def test_groups_have_no_alpha():
    with pytest.raises(ValueError, match="alpha: this float32 image goes through as 6 channels in groups"):
        pp.convert(rng.random((64, 128, 6)).astype(np.float32), "equirect", "pinhole", alpha=True)
    with pytest.raises(ValueError, match="fill: this int32 image goes through as its samples as bytes"):
        pp.convert(np.zeros((64, 128), np.int32), "equirect", "pinhole", interp="nearest", fill=(1, 0, 0))


def test_a_batch_equals_its_frames_converted_one_by_one():
    frames = np.stack([np.roll(IMG, 17 * i, axis=1) for i in range(8)])
    out = pp.convert(frames, "equirect", "pinhole:hfov=80", size=(64, 48), yaw=30)
    assert out.shape == (8, 48, 64, 3) and out.dtype == np.uint8
    for i in range(8):
        np.testing.assert_array_equal(out[i], pp.convert(frames[i], "equirect", "pinhole:hfov=80", size=(64, 48),
                                                         yaw=30))
    plan = pp.Plan("equirect", "pinhole:hfov=80", (256, 128), size=(64, 48), yaw=30)
    np.testing.assert_array_equal(plan(frames), out)
    labels = np.stack([_labels((128, 256))[..., None]] * 3).astype(np.int32)  # batches of labels, of float64
    assert set(np.unique(pp.convert(labels, "equirect", "pinhole", interp="nearest"))) <= set(np.unique(labels))
    assert pp.convert(frames / 255.0, "equirect", "pinhole", size=(8, 8)).dtype == np.float64


class _DLPackOnly:
    """An array known only by the DLPack protocol (what torch, JAX and CuPy hand over)."""

    def __init__(self, a):
        self._a = a

    def __dlpack__(self, **kwargs):
        return self._a.__dlpack__(**kwargs)

    def __dlpack_device__(self):
        return self._a.__dlpack_device__()


class _ArrayOnly:
    def __init__(self, a):
        self._a = a

    def __array__(self, dtype=None, copy=None):
        return self._a


@pytest.mark.parametrize("wrap", [_DLPackOnly, _ArrayOnly, memoryview, lambda a: a.tolist()],
                         ids=["dlpack", "__array__", "memoryview", "list"])
def test_array_likes_convert_as_their_arrays(wrap):
    small = IMG[::4, ::4].copy()
    ref = pp.convert(small, "equirect", "pinhole", size=(16, 16), interp="nearest")
    out = pp.convert(wrap(small), "equirect", "pinhole", size=(16, 16), interp="nearest")
    np.testing.assert_array_equal(out, ref)  # (a list of ints is numpy's int64: the same values)


def test_a_list_of_six_array_likes_is_faces_and_a_dict_by_face_too():
    cube = pp.convert(IMG, "equirect", "cubemap", size=(6 * 32, 32))
    faces = pp.split_faces(cube)
    ref = pp.convert(faces, "cubemap", "equirect", size=(128, 64))
    by_letter = dict(zip("FRBLUD", faces))
    by_name = dict(zip(["front", "right", "back", "left", "up", "down"], faces))
    for given in (tuple(faces), [_DLPackOnly(np.ascontiguousarray(f)) for f in faces], by_letter, by_name):
        np.testing.assert_array_equal(pp.convert(given, "cubemap", "equirect", size=(128, 64)), ref)
    with pytest.raises(ValueError, match=r"cube faces: keys \['B', 'D', 'F', 'L', 'R', 'X'\] \(expected F R B L U D"):
        pp.convert({**{k: v for k, v in by_letter.items() if k != "U"}, "X": faces[0]}, "cubemap", "equirect")
    with pytest.raises(ValueError, match=r"cube faces: 5 arrays \(expected 6"):
        pp.convert(faces[:5], "cubemap", "equirect")


def test_channels_first_gets_the_transpose_it_needs():
    with pytest.raises(ValueError, match=r"array shape \(3, 128, 256\): channels first \(CHW\) \(expected channels "
                                         r"last: np.moveaxis\(a, -3, -1\)\)"):
        pp.convert(np.moveaxis(IMG, -1, 0), "equirect", "pinhole")
    with pytest.raises(ValueError, match=r"\(2, 3, 128, 256\): channels first"):
        pp.convert(np.stack([np.moveaxis(IMG, -1, 0)] * 2), "equirect", "pinhole")


def test_a_swapped_size_for_an_equirect_target_warns():
    with pytest.warns(UserWarning, match=r"size=\(32, 64\) is \(width, height\).*did you mean size=\(64, 32\)\?"):
        pp.convert(IMG, "equirect", "equirect", size=(32, 64))
    with pytest.warns(UserWarning, match=r"did you mean size=\(64, 32\)"):
        pp.build_map("equirect", "equirect", (256, 128), size=(32, 64))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        pp.convert(IMG, "equirect", "equirect", size=(64, 32))
        pp.convert(IMG, "equirect", "equirect:hfov=90,vfov=180", size=(32, 64))  # 1:2 is right here


@pytest.mark.parametrize("call,cls,text", [
    (lambda: pp.convert(IMG, "equirect", "pinhole", interp=1), TypeError, "interp: 1 (expected text)"),
    (lambda: pp.convert(IMG, "equirect", "pinhole", interp="linaer"), ValueError,
     "interp: 'linaer' (expected one of nearest, bilinear, bicubic, lanczos3, bicubic-dering, lanczos3-dering; did "
     "you mean 'bilinear'?)"),
    (lambda: pp.convert(IMG, "equirect", "pinhole", intrp="bilinear"), TypeError,
     "convert: unknown option 'intrp' (did you mean 'interp'?"),
    (lambda: pp.build_map("equirect", "pinhole", None), TypeError, "source_size: None (expected the source image's"),
    (lambda: pp.Plan("equirect", "pinhole", None), TypeError, "source_size: None"),
    (lambda: pp.to_ray("equirect", None, [0.5], [0.5]), TypeError, "source_size: None"),
    (lambda: pp.convert(IMG, "equirect", "perspective"), ValueError, "did you mean pinhole?"),
    (lambda: pp.convert(IMG, "equirectangular", "pinhole"), ValueError, "did you mean equirect?"),
    (lambda: pp.convert(IMG, "equirect", "cube"), ValueError, "did you mean cubemap?"),
    (lambda: pp.convert(IMG, "equirect", "dice"), ValueError, "did you mean cubemap:layout=cross?"),
    (lambda: pp.convert(IMG, "equirect", "horizon"), ValueError, "did you mean cubemap:layout=6x1?"),
    (lambda: pp.convert(IMG, "equirect", "fishey"), ValueError, "did you mean fisheye?"),
    (lambda: pp.convert(IMG, "equirect", "pinhole", convention="x"), TypeError, "unknown option 'convention'"),
    (lambda: pp.build_map("equirect", "pinhole", (8, 4), convention="cv2"), ValueError,
     "convention: 'cv2' (expected 'panoproj', 'opencv' or 'torch')"),
    (lambda: pp.convert(None, "equirect", "pinhole"), TypeError, "image: NoneType (expected an array"),
    (lambda: pp.convert(b"pano", "equirect", "pinhole"), TypeError, "read files with panoproj.read"),
    (lambda: pp.convert("pano.jpg", "equirect", "pinhole"), FileNotFoundError, "input pano.jpg does not exist"),
])
def test_traps_are_one_pythonic_line(call, cls, text):
    with pytest.raises(cls) as e:
        call()
    message = str(e.value)
    assert text in message and "\n" not in message and "incompatible function arguments" not in message, message
