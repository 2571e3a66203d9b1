"""Calibrated lens models against OpenCV's own implementation, as a test-only oracle:
panoproj's kannala-brandt (spec keys in OpenCV's conventions) against cv2.fisheye's
distortPoints / undistortPoints, within 1e-3 px, for fields under 180 degrees (OpenCV works on
x/z and y/z, so it cannot go further; panoproj's own round trips beyond it are in ctest)."""
import cv2
import numpy as np
import pytest

import panoproj as pp

# A 1920x1080 camera as cv2.fisheye.calibrate returns it, and a stronger, anisotropic one.
LENSES = [
    dict(fx=620.5, fy=621.3, cx=959.2, cy=541.7, k=(0.0361, -0.0112, 0.0028, -0.0004)),
    dict(fx=410.0, fy=395.0, cx=947.0, cy=530.5, k=(-0.012, 0.021, -0.009, 0.0013)),
]
SIZE = (1920, 1080)


def spec(lens, fov=178):
    k1, k2, k3, k4 = lens["k"]
    return (f"kannala-brandt:fov={fov},fx={lens['fx']},fy={lens['fy']},cx={lens['cx']},cy={lens['cy']},"
            f"k1={k1},k2={k2},k3={k3},k4={k4}")


def camera(lens):
    K = np.array([[lens["fx"], 0, lens["cx"]], [0, lens["fy"], lens["cy"]], [0, 0, 1]], np.float64)
    return K, np.array(lens["k"], np.float64).reshape(4, 1)


def rays_under(theta_max_deg, n=4000, seed=3):
    rng = np.random.default_rng(seed)
    theta = np.deg2rad(theta_max_deg) * np.sqrt(rng.random(n))
    phi = rng.random(n) * 2 * np.pi
    return np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], -1)


@pytest.mark.parametrize("lens", LENSES, ids=["calibrated", "anisotropic"])
def test_pixels_match_cv2_fisheye_distort_points(lens):
    rays = rays_under(88)
    x, y, ok = pp.to_pixel(spec(lens), SIZE, rays)
    K, D = camera(lens)
    # OpenCV's normalized points are (x/z, y/z); its pixel centres are at integers, panoproj's
    # at i + 0.5.
    undist = (rays[:, :2] / rays[:, 2:3]).reshape(-1, 1, 2)
    theirs = cv2.fisheye.distortPoints(undist, K, D).reshape(-1, 2)
    inside = ok & (theirs[:, 0] > 0) & (theirs[:, 0] < SIZE[0] - 1) & (theirs[:, 1] > 0) & (theirs[:, 1] < SIZE[1] - 1)
    assert inside.sum() > 1000
    err = np.hypot(x - 0.5 - theirs[:, 0], y - 0.5 - theirs[:, 1])[inside]
    assert err.max() < 1e-3, err.max()


@pytest.mark.parametrize("lens", LENSES, ids=["calibrated", "anisotropic"])
def test_rays_match_cv2_fisheye_undistort_points(lens):
    K, D = camera(lens)
    gx, gy = np.meshgrid(np.arange(0, SIZE[0], 37.3), np.arange(0, SIZE[1], 29.1))
    px = np.stack([gx.ravel(), gy.ravel()], -1)  # OpenCV pixel positions
    rays, ok = pp.to_ray(spec(lens), SIZE, px[:, 0] + 0.5, px[:, 1] + 0.5)
    # Up to 85 degrees from the axis, where x/z stays well conditioned for OpenCV's iteration.
    near = ok & (rays[:, 2] > np.cos(np.deg2rad(85)))
    assert near.sum() > 500
    crit = (cv2.TERM_CRITERIA_COUNT + cv2.TERM_CRITERIA_EPS, 100, 1e-14)
    und = cv2.fisheye.undistortPoints(px[near].reshape(-1, 1, 2), K, D, criteria=crit).reshape(-1, 2)
    ours = rays[near, :2] / rays[near, 2:3]
    # Compared in pixels: the difference of normalized points times the focal length.
    err = np.hypot((ours[:, 0] - und[:, 0]) * lens["fx"], (ours[:, 1] - und[:, 1]) * lens["fy"])
    assert err.max() < 1e-3, err.max()


def test_beyond_180_degrees_round_trips():
    # Where OpenCV's functions stop: a 220-degree lens, pixels -> rays -> pixels.
    lens = LENSES[0]
    s = spec(lens, fov=220)
    gx, gy = np.meshgrid(np.arange(0.5, SIZE[0], 13.0), np.arange(0.5, SIZE[1], 11.0))
    rays, ok = pp.to_ray(s, SIZE, gx.ravel(), gy.ravel())
    back_x, back_y, ok2 = pp.to_pixel(s, SIZE, rays[ok])
    assert ok2.all()
    assert (rays[ok, 2] < 0).any()  # some rays look behind the camera
    err = np.hypot(back_x - gx.ravel()[ok], back_y - gy.ravel()[ok])
    assert err.max() < 1e-3
