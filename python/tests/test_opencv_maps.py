"""cv2.remap with panoproj.build_map reproduces panoproj's bilinear output (within 1 LSB on a
smooth image), away from what cv2.remap cannot do: seams, poles and cube face edges."""
import cv2
import numpy as np
import pytest

import panoproj as pp
from conftest import smooth_equirect

W, H = 1024, 512
CASES = [
    ("pinhole:hfov=90", (640, 480), dict(yaw=40, pitch=10)),
    ("fisheye:fov=180", (512, 512), dict(pitch=-30)),
    ("cubemap", (6 * 200, 200), {}),
    ("equirect", (800, 400), dict(yaw=12.3, roll=7)),
]


@pytest.mark.parametrize("dst,size,angles", CASES, ids=[c[0] for c in CASES])
def test_cv2_remap_with_our_maps_matches_our_bilinear(dst, size, angles):
    img = smooth_equirect(W, H)
    # cv2.remap has no antialiasing: compare without.
    ours = pp.convert(img, "equirect", dst, size=size, interp="bilinear", antialias="off", **angles)
    mx, my = pp.build_map("equirect", dst, (W, H), size=size, **angles)
    assert mx.dtype == np.float32 and mx.shape == (size[1], size[0])
    theirs = cv2.remap(img, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT)
    # Where cv2.remap is on its own: taps must not cross the seam or a pole (x in [0, W-1),
    # y in [0, H-1)); on a cube face, 2 px from its edges.
    away = (mx >= 1) & (mx <= W - 2) & (my >= 1) & (my <= H - 2)
    if dst == "cubemap":
        u = np.arange(size[0]) % size[1]
        v = np.arange(size[1])
        inner = ((u >= 2) & (u < size[1] - 2))[None, :] & ((v >= 2) & (v < size[1] - 2))[:, None]
        away &= inner
    assert away.mean() > 0.5
    diff = np.abs(ours.astype(int) - theirs.astype(int)).max(axis=-1)
    assert diff[away].max() <= 1
    # And the maps are not trivially right: half a pixel off is caught.
    slipped = cv2.remap(img, mx + 0.5, my, cv2.INTER_LINEAR)
    assert np.abs(ours.astype(int) - slipped.astype(int)).max(axis=-1)[away].max() > 1
