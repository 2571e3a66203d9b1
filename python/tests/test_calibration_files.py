"""Calibration files users hold, read as specs: OCamCalib's calib_results.txt (its law against the
toolbox's own cam2world formula, written here from its C code, and its fitted invpol reported by
`panoproj accuracy`), NVIDIA's f-theta polynomial (against its forward formula), and Kalibr's
camchain.yaml (each camera_model / distortion_model pair as the spec it names)."""
import subprocess

import numpy as np
import pytest

import panoproj as pp

# A 190-degree fisheye on 1024x768 in OCamCalib's form: pol (pixel -> ray), centre (row, column),
# affine c, d, e.
POL = [-244.5239, 0.0, 0.0017486, -2.904e-06, 1.046e-08]
XC, YC = 383.943115, 511.652588
C, D, E = 1.000144, 0.000114, -0.000153
SIZE = (1024, 768)


def cam2world(px):
    """OCamCalib's cam2world (ocam_functions.c) for pixel positions in panoproj's convention (a
    pixel's centre at i + 0.5; OCamCalib's at i): its (x, y, z) with x along rows, then panoproj's
    axes (x right, y down, z forward): (y, x, -z)."""
    row, col = px[:, 1] - 0.5, px[:, 0] - 0.5
    invdet = 1 / (C - D * E)
    xp = invdet * ((row - XC) - D * (col - YC))
    yp = invdet * (-E * (row - XC) + C * (col - YC))
    rho = np.hypot(xp, yp)
    zp = np.polyval(POL[::-1], rho)
    v = np.stack([yp, xp, -zp], -1)
    return v / np.linalg.norm(v, axis=1)[:, None]


def fitted_invpol(theta_max, degree=12):
    """The toolbox's invpol: rho as a polynomial in theta' = theta - pi/2, fitted (least squares)."""
    rho = np.linspace(0, 700, 20001)
    theta = np.arctan2(rho, -np.polyval(POL[::-1], rho))
    keep = theta <= theta_max
    return np.polyfit(theta[keep] - np.pi / 2, rho[keep], degree)[::-1]


def write_calib_results(path, invpol):
    path.write_text(
        "#polynomial coefficients for the DIRECT mapping function (ocam_model.ss in MATLAB). These are used by cam2world\n\n"
        f"{len(POL)} " + " ".join(f"{v:.6e}" for v in POL) + " \n\n"
        "#polynomial coefficients for the inverse mapping function (ocam_model.invpol in MATLAB). These are used by world2cam\n\n"
        f"{len(invpol)} " + " ".join(repr(float(v)) for v in invpol) + " \n\n"
        '#center: "row" and "column", starting from 0 (C convention)\n\n'
        f"{XC:.6f} {YC:.6f}\n\n"
        '#affine parameters "c", "d", "e"\n\n'
        f"{C:.6f} {D:.6f} {E:.6f}\n\n"
        '#image size: "height" and "width"\n\n'
        f"{SIZE[1]} {SIZE[0]}\n")


def angle(a, b):
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.sum(a * b, axis=1))


def test_ocamcalib_calib_results_is_its_cam2world_law(tmp_path):
    invpol = fitted_invpol(np.deg2rad(97))
    write_calib_results(tmp_path / "calib_results.txt", invpol)
    spec = pp.projection(f"@{tmp_path / 'calib_results.txt'}")
    assert str(spec).startswith("ocamcalib:xc=383.943115,yc=511.652588,pol=-2.445239e+02/")
    rng = np.random.default_rng(3)
    px = np.stack([rng.random(100_000) * SIZE[0], rng.random(100_000) * SIZE[1]], -1)
    ours, ok = pp.to_ray(spec, SIZE, px[:, 0], px[:, 1])
    assert ok.mean() > 0.5
    err = angle(ours[ok], cam2world(px[ok]))
    print(f"\nocamcalib pixel -> ray, {ok.sum()} pixels: max {err.max():.2e} rad vs OCamCalib's cam2world")
    assert err.max() < 1e-9
    # Ray -> pixel (panoproj's bracketed Newton on pol) back onto the pixels cam2world lifted.
    x, y, ok2 = pp.to_pixel(spec, SIZE, cam2world(px[ok]))
    assert ok2.all()
    e2 = np.hypot(x - px[ok, 0], y - px[ok, 1])
    print(f"ray -> pixel: max {e2.max():.2e} px")
    assert e2.max() < 1e-9


def test_ocamcalib_fitted_invpol_is_reported_not_used(cli, tmp_path):
    invpol = fitted_invpol(np.deg2rad(97), degree=6)  # a coarse fit: a visible difference
    write_calib_results(tmp_path / "calib_results.txt", invpol)
    spec = f"@{tmp_path / 'calib_results.txt'}"
    lens = pp.projection(spec)
    # The exact inverse against the fit over the field panoproj gives the frame.
    rays = cam2world(np.stack([np.linspace(YC + 0.5, SIZE[0], 2000), np.full(2000, XC + 0.5)], -1))
    x, y, ok = pp.to_pixel(lens, SIZE, rays)
    theta = np.arccos(rays[:, 2])
    rho_fit = np.polyval(invpol[::-1], theta - np.pi / 2)
    diff = np.abs(rho_fit - np.hypot(x - YC - 0.5, y - XC - 0.5))[ok]
    run = subprocess.run([cli, "accuracy", "--from", spec, "--from-size", "1024x768", "--to", "equirect", "--size",
                          "256x128", "--interp", "bilinear", "--antialias", "off", "--engine", "simd", "--runs", "1"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    line = [s for s in run.stdout.splitlines() if "fitted invpol" in s]
    assert line, run.stdout
    reported = float(line[0].split("is up to ")[1].split(" px")[0])
    print(f"\n{line[0]}\n(this test measures {diff.max():.3g} px along one radius)")
    assert diff.max() > 1e-3  # the coarse fit differs, and the report says by how much
    assert reported >= diff.max() * 0.99 and reported < diff.max() * 3


def ftheta_pixels(rays, poly, cx, cy, cde):
    """NVIDIA's f-theta forward model: r = poly(theta) pixels along the ray's azimuth, then the
    linear term [[c, d], [e, 1]] about the principal point."""
    theta = np.arctan2(np.hypot(rays[:, 0], rays[:, 1]), rays[:, 2])
    phi = np.arctan2(rays[:, 1], rays[:, 0])
    r = np.polyval(poly[::-1], theta)
    u, v = r * np.cos(phi), r * np.sin(phi)
    c, d, e = cde
    return np.stack([cx + c * u + d * v, cy + e * u + v], -1)


def test_f_theta_is_its_forward_polynomial(cli, tmp_path):
    poly = np.array([0, 1090.6, -12.8, -34.1, 6.2, -0.55])
    cx, cy, cde = 1925.4, 1084.6, (1.0003, 0.0002, -0.0001)
    size = (3848, 2168)
    spec = (f"f-theta:fov=200,cx={cx - 0.5},cy={cy - 0.5},poly=" + "/".join(map(str, poly)) +
            f",c={cde[0]},d={cde[1]},e={cde[2]}")
    rng = np.random.default_rng(4)
    z = 1 - (1 - np.cos(np.deg2rad(100))) * rng.random(100_000)
    phi = rng.random(100_000) * 2 * np.pi
    rays = np.stack([np.sqrt(1 - z * z) * np.cos(phi), np.sqrt(1 - z * z) * np.sin(phi), z], -1)
    x, y, ok = pp.to_pixel(spec, size, rays)
    law = ftheta_pixels(rays, poly, cx, cy, cde)
    err = np.hypot(x - law[:, 0], y - law[:, 1])[ok]
    assert ok.sum() > 50_000
    print(f"\nf-theta ray -> pixel, {ok.sum()} rays to 100 deg: max {err.max():.2e} px vs the forward polynomial")
    assert err.max() < 1e-9
    back, ok2 = pp.to_ray(spec, size, x[ok], y[ok])
    assert ok2.all() and angle(back, rays[ok]).max() < 1e-9
    # A calibration's bw_poly (fitted here, as NVIDIA's tools do) is only compared.
    t = np.linspace(0, np.deg2rad(100), 5000)
    bw = np.polyfit(np.polyval(poly[::-1], t), t, 5)[::-1]
    run = subprocess.run([cli, "accuracy", "--from", spec + ",bw_poly=" + "/".join(repr(float(v)) for v in bw), "--from-size",
                          "3848x2168", "--to", "equirect", "--size", "256x128", "--interp", "bilinear", "--antialias",
                          "off", "--engine", "simd", "--runs", "1"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert "fitted bw_poly is up to" in run.stdout, run.stdout


CAMCHAIN = """cam0:
  cam_overlaps: [1]
  camera_model: omni
  distortion_coeffs: [-0.0346, 0.0236, 0.0004, -0.0009]
  distortion_model: radtan
  intrinsics: [1.82, 741.5, 740.7, 639.6, 511.2]
  resolution: [1280, 1024]
  rostopic: /cam0/image_raw
cam1:
  T_cn_cnm1:
  - [0.9999, 0.0021, -0.0113, -0.1101]
  - [-0.0021, 1.0, 0.0003, 0.0002]
  - [0.0113, -0.0003, 0.9999, 0.0004]
  - [0.0, 0.0, 0.0, 1.0]
  cam_overlaps: [0]
  camera_model: ds
  distortion_coeffs: []
  distortion_model: none
  intrinsics: [-0.18, 0.59, 313.2, 313.1, 638.9, 514.6]
  resolution: [1280, 1024]
  rostopic: /cam1/image_raw
"""


@pytest.mark.parametrize("model,dist,intrinsics,coeffs,expected", [
    ("pinhole", "radtan", "[458.654, 457.296, 367.215, 248.375]", "[-0.2834, 0.0739, 0.0002, 1.76e-05]",
     "brown-conrady:fx=458.654,fy=457.296,cx=367.215,cy=248.375,k1=-0.2834,k2=0.0739,p1=0.0002,p2=1.76e-05,width=1024,height=1024"),
    ("pinhole", "equidistant", "[380.8, 380.6, 510.3, 514.3]", "[0.0101, -0.0055, 0.0008, -0.0001]",
     "kannala-brandt:fx=380.8,fy=380.6,cx=510.3,cy=514.3,k1=0.0101,k2=-0.0055,k3=0.0008,k4=-0.0001,width=1024,height=1024"),
    ("pinhole", "fov", "[380.8, 380.6, 510.3, 514.3]", "[0.93]",
     "devernay-faugeras:fx=380.8,fy=380.6,cx=510.3,cy=514.3,omega=0.93,width=1024,height=1024"),
    ("omni", "none", "[0.95, 380.8, 380.6, 510.3, 514.3]", "[]", "unified:xi=0.95,fx=380.8,fy=380.6,cx=510.3,cy=514.3,width=1024,height=1024"),
    ("eucm", "none", "[0.63, 1.04, 380.8, 380.6, 510.3, 514.3]", "[]",
     "extended-unified:alpha=0.63,beta=1.04,fx=380.8,fy=380.6,cx=510.3,cy=514.3,width=1024,height=1024"),
])
def test_kalibr_camchain_models(tmp_path, model, dist, intrinsics, coeffs, expected):
    (tmp_path / "camchain.yaml").write_text(
        f"cam0:\n  camera_model: {model}\n  distortion_coeffs: {coeffs}\n  distortion_model: {dist}\n"
        f"  intrinsics: {intrinsics}\n  resolution: [1024, 1024]\n")
    assert str(pp.projection(f"@{tmp_path / 'camchain.yaml'}")) == str(pp.projection(expected))


def test_kalibr_camchain_picks_a_camera(tmp_path):
    path = tmp_path / "camchain.yaml"
    path.write_text(CAMCHAIN)
    assert str(pp.projection(f"@{path}#cam0")) == str(pp.projection(
        "omni-radtan:xi=1.82,fx=741.5,fy=740.7,cx=639.6,cy=511.2,k1=-0.0346,k2=0.0236,p1=0.0004,p2=-0.0009,width=1280,"
        "height=1024"))
    assert str(pp.projection(f"@{path}#cam1")) == str(pp.projection(
        "double-sphere:xi=-0.18,alpha=0.59,fx=313.2,fy=313.1,cx=638.9,cy=514.6,width=1280,height=1024"))
    # Its resolution is the calibrated size: an image of another size is refused.
    with pytest.raises(ValueError, match=r"the calibration is of 1280x1024 images, this frame is 640x512"):
        pp.to_ray(f"@{path}#cam0", (640, 512), np.array([1.0]), np.array([1.0]))
    with pytest.raises(ValueError, match=r"holds cameras cam0, cam1 \(name one"):
        pp.projection(f"@{path}")
    with pytest.raises(ValueError, match=r"no camera cam2 \(it holds cam0, cam1\)"):
        pp.projection(f"@{path}#cam2")
    path.write_text(CAMCHAIN.replace("camera_model: ds", "camera_model: ds\n  bogus: 1").replace(
        "distortion_model: none", "distortion_model: equidistant", 1))
    with pytest.raises(ValueError, match="camera_model ds with distortion_model equidistant"):
        pp.projection(f"@{path}#cam1")
