"""Calibrated lens models against OpenCV's own implementation, as a test-only oracle (spec keys in
OpenCV's conventions): panoproj's kannala-brandt against cv2.fisheye's distortPoints /
undistortPoints, for fields under 180 degrees (OpenCV works on x/z and y/z, so it cannot go
further; panoproj's own round trips beyond it are in ctest), and brown-conrady against
cv2.projectPoints / cv2.undistortPoints; all within 1e-3 px."""
import os
import subprocess

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


# Brown-Conrady cameras (k1, k2, p1, p2, k3): barrel with tangential terms, and pincushion.
CAMERAS = [
    dict(fx=1000.0, fy=1002.0, cx=959.5, cy=539.5, d=(-0.28, 0.09, 0.001, -0.0005, -0.01)),
    dict(fx=800.0, fy=800.0, cx=951.0, cy=548.25, d=(0.15, 0.02, -0.004, 0.003, 0.0)),
]


def brown_spec(cam):
    k1, k2, p1, p2, k3 = cam["d"]
    return (f"brown-conrady:fx={cam['fx']},fy={cam['fy']},cx={cam['cx']},cy={cam['cy']},"
            f"k1={k1},k2={k2},p1={p1},p2={p2},k3={k3}")


@pytest.mark.parametrize("cam", CAMERAS, ids=["barrel", "pincushion"])
def test_brown_conrady_matches_cv2_project_and_undistort_points(cam):
    K = np.array([[cam["fx"], 0, cam["cx"]], [0, cam["fy"], cam["cy"]], [0, 0, 1]], np.float64)
    D = np.array(cam["d"], np.float64)
    rays = rays_under(45)
    x, y, ok = pp.to_pixel(brown_spec(cam), SIZE, rays)
    theirs, _ = cv2.projectPoints(rays.reshape(-1, 1, 3), np.zeros(3), np.zeros(3), K, D)
    theirs = theirs.reshape(-1, 2)
    assert ok.sum() > 1000
    assert np.hypot(x - 0.5 - theirs[:, 0], y - 0.5 - theirs[:, 1])[ok].max() < 1e-3
    # Pixels -> rays against cv2.undistortPoints (iterated to convergence).
    gx, gy = np.meshgrid(np.arange(0, SIZE[0], 41.3), np.arange(0, SIZE[1], 33.7))
    px = np.stack([gx.ravel(), gy.ravel()], -1)
    ours, ok = pp.to_ray(brown_spec(cam), SIZE, px[:, 0] + 0.5, px[:, 1] + 0.5)
    assert ok.all()
    crit = (cv2.TERM_CRITERIA_COUNT + cv2.TERM_CRITERIA_EPS, 200, 1e-15)
    und = cv2.undistortPoints(px.reshape(-1, 1, 2), K, D, None, None, None, crit).reshape(-1, 2)
    mine = ours[:, :2] / ours[:, 2:3]
    err = np.hypot((mine[:, 0] - und[:, 0]) * cam["fx"], (mine[:, 1] - und[:, 1]) * cam["fy"])
    assert err.max() < 1e-3, err.max()


def test_a_calibration_file_is_a_spec(tmp_path):
    # The calibration kept beside the photos: JSON or YAML, the same projection as the spec text.
    lens = LENSES[0]
    k1, k2, k3, k4 = lens["k"]
    (tmp_path / "lens.yaml").write_text(
        f"projection: kannala-brandt\nfov: 178\nfx: {lens['fx']}\nfy: {lens['fy']}\ncx: {lens['cx']}\n"
        f"cy: {lens['cy']}\nk1: {k1}\nk2: {k2}\nk3: {k3}\nk4: {k4}\n")
    from_file = pp.projection(f"@{tmp_path / 'lens.yaml'}")
    assert str(from_file) == str(pp.projection(spec(lens)))
    rays = rays_under(80, n=200)
    a = pp.to_pixel(from_file, SIZE, rays)
    b = pp.to_pixel(spec(lens), SIZE, rays)
    assert np.array_equal(a[0], b[0], equal_nan=True) and np.array_equal(a[1], b[1], equal_nan=True)
    with pytest.raises(ValueError, match="no \"projection\" key"):
        (tmp_path / "bad.json").write_text('{"fx": 1}')
        pp.projection(f"@{tmp_path / 'bad.json'}")


# OpenCV's full model: rational k4..k6 and thin prism s1..s4 (cv2.projectPoints with the
# 12-coefficient vector, CALIB_RATIONAL_MODEL | CALIB_THIN_PRISM_MODEL's order).
FULL = [
    dict(fx=700.0, fy=702.0, cx=958.3, cy=541.2,
         d=(2.1, 0.9, 0.0004, -0.0003, 0.02, 2.45, 1.6, 0.15, 0.001, -0.0002, -0.0008, 0.0001)),
    dict(fx=900.0, fy=900.0, cx=951.0, cy=548.25, d=(-0.25, 0.06, 0.0, 0.0, 0.0, 0.1, 0.0, 0.0, 0.004, 0.0, -0.003, 0.0)),
]
FULL_KEYS = ("k1", "k2", "p1", "p2", "k3", "k4", "k5", "k6", "s1", "s2", "s3", "s4")


def full_spec(cam):
    keys = ",".join(f"{k}={v}" for k, v in zip(FULL_KEYS, cam["d"]))
    return f"brown-conrady:fx={cam['fx']},fy={cam['fy']},cx={cam['cx']},cy={cam['cy']},{keys}"


@pytest.mark.parametrize("cam", FULL, ids=["rational", "thin-prism"])
def test_rational_and_thin_prism_match_cv2_project_points(cam):
    K = np.array([[cam["fx"], 0, cam["cx"]], [0, cam["fy"], cam["cy"]], [0, 0, 1]], np.float64)
    D = np.array(cam["d"], np.float64)
    rays = rays_under(50, n=100_000)
    x, y, ok = pp.to_pixel(full_spec(cam), SIZE, rays)
    theirs, _ = cv2.projectPoints(rays.reshape(-1, 1, 3), np.zeros(3), np.zeros(3), K, D)
    theirs = theirs.reshape(-1, 2)
    assert ok.sum() > 10_000
    err = np.hypot(x - 0.5 - theirs[:, 0], y - 0.5 - theirs[:, 1])[ok]
    print(f"\n{full_spec(cam)}: ray -> pixel, {ok.sum()} points: max {err.max():.2e} px vs cv2.projectPoints")
    assert err.max() < 1e-9, err.max()
    # Pixels -> rays against cv2.undistortPoints iterated to convergence.
    gx, gy = np.meshgrid(np.arange(0, SIZE[0], 21.3), np.arange(0, SIZE[1], 17.7))
    px = np.stack([gx.ravel(), gy.ravel()], -1)
    ours, ok = pp.to_ray(full_spec(cam), SIZE, px[:, 0] + 0.5, px[:, 1] + 0.5)
    assert ok.sum() > 1000
    crit = (cv2.TERM_CRITERIA_COUNT + cv2.TERM_CRITERIA_EPS, 500, 1e-16)
    und = cv2.undistortPoints(px[ok].reshape(-1, 1, 2), K, D, None, None, None, crit).reshape(-1, 2)
    mine = ours[ok, :2] / ours[ok, 2:3]
    e2 = np.hypot((mine[:, 0] - und[:, 0]) * cam["fx"], (mine[:, 1] - und[:, 1]) * cam["fy"])
    # OpenCV's undistortPoints iterates a fixed-point scheme: how far its own result is from
    # reprojecting onto the pixel bounds the comparison.
    back, _ = cv2.projectPoints(np.concatenate([und, np.ones((len(und), 1))], 1).reshape(-1, 1, 3), np.zeros(3),
                                np.zeros(3), K, D)
    own = np.hypot(*(back.reshape(-1, 2) - px[ok]).T)
    good = own < 1e-9
    print(f"pixel -> ray, {good.sum()} points (cv2's own round trip under 1e-9 px; {(~good).sum()} excluded): "
          f"max {e2[good].max():.2e} px vs cv2.undistortPoints")
    assert good.sum() > 500 and e2[good].max() < 1e-9


# Mei's omnidirectional model with radtan, as Kalibr and cv2.omnidir calibrate it (an Insta360
# lens's xi past 1, and a catadioptric xi under it).
OMNI = [
    dict(xi=1.82, fx=741.5, fy=740.7, cx=639.6, cy=511.2, d=(-0.0346, 0.0236, 0.0004, -0.0009), size=(1280, 1024)),
    dict(xi=0.9, fx=380.0, fy=381.0, cx=512.5, cy=511.0, d=(-0.1, 0.02, 0.001, 0.002), size=(1024, 1024)),
]
OMNIDIR_PYTHON = os.path.join(os.path.dirname(__file__), "..", "..", ".venv-omnidir", "bin", "python")


def omni_spec(cam, k3=0.0):
    k1, k2, p1, p2 = cam["d"]
    return (f"omni-radtan:xi={cam['xi']},fx={cam['fx']},fy={cam['fy']},cx={cam['cx']},cy={cam['cy']},"
            f"k1={k1},k2={k2},p1={p1},p2={p2},k3={k3}")


def omni_law(cam, rays, k3):
    """Mei's projection with radtan and k3, from the formulas (Mei and Rives 2007; OpenCV's radtan)."""
    xs = rays / np.linalg.norm(rays, axis=1)[:, None]
    x, y = xs[:, 0] / (xs[:, 2] + cam["xi"]), xs[:, 1] / (xs[:, 2] + cam["xi"])
    k1, k2, p1, p2 = cam["d"]
    r2 = x * x + y * y
    radial = 1 + k1 * r2 + k2 * r2 * r2 + k3 * r2**3
    xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x)
    yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y
    return np.stack([cam["fx"] * xd + cam["cx"], cam["fy"] * yd + cam["cy"]], -1)


@pytest.mark.parametrize("cam", OMNI, ids=["xi-1.82", "xi-0.9"])
def test_omni_radtan_matches_cv2_omnidir(cam, tmp_path):
    """cv2.omnidir lives in opencv-contrib, which cannot share a venv with opencv-python: it runs in
    .venv-omnidir (scripts/python-env.sh) on the rays written here."""
    if not os.path.exists(OMNIDIR_PYTHON):
        pytest.skip(".venv-omnidir is missing (scripts/python-env.sh makes it)")
    rays = rays_under(120, n=100_000)
    x, y, ok = pp.to_pixel(omni_spec(cam), cam["size"], rays)
    np.save(tmp_path / "rays.npy", rays)
    code = ("import cv2, numpy as np, sys; r = np.load(sys.argv[1]); K = np.array(" + repr(
        [[cam["fx"], 0, cam["cx"]], [0, cam["fy"], cam["cy"]], [0, 0, 1]]) + ", np.float64); "
            "p, _ = cv2.omnidir.projectPoints(r.reshape(1, -1, 3), np.zeros((1, 3)), np.zeros((1, 3)), K, "
            f"{cam['xi']!r}, np.array([{list(cam['d'])!r}], np.float64)); np.save(sys.argv[2], p.reshape(-1, 2))")
    subprocess.run([OMNIDIR_PYTHON, "-c", code, str(tmp_path / "rays.npy"), str(tmp_path / "px.npy")], check=True)
    theirs = np.load(tmp_path / "px.npy")
    assert ok.sum() > 10_000
    err = np.hypot(x - 0.5 - theirs[:, 0], y - 0.5 - theirs[:, 1])[ok]
    print(f"\n{omni_spec(cam)}: {ok.sum()} rays to 120 deg, max {err.max():.2e} px vs cv2.omnidir.projectPoints")
    assert err.max() < 1e-9, err.max()
    # k3, which cv2.omnidir lacks: against the formula.
    k3 = -0.004
    x, y, ok = pp.to_pixel(omni_spec(cam, k3), cam["size"], rays)
    law = omni_law(cam, rays, k3)
    e3 = np.hypot(x - 0.5 - law[:, 0], y - 0.5 - law[:, 1])[ok]
    print(f"with k3={k3}: max {e3.max():.2e} px vs the closed form")
    assert e3.max() < 1e-9
    # And the spec without k3 is the formula too (the oracle of the oracle).
    assert np.hypot(*(omni_law(cam, rays[ok], 0.0) - theirs[ok]).T).max() < 1e-9
