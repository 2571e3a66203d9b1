"""panoproj's calibrated lenses against COLMAP's own camera models (pycolmap 4.2 from pip, a test-only
oracle), model by model on 10^5 random rays and 10^5 random pixels: ray -> pixel against
img_from_cam within 1e-9 px, pixel -> ray against cam_ray_from_img within 1e-9 rad where COLMAP's
inverse is closed, and within 10x COLMAP's own round-trip error where it iterates. COLMAP's
fisheye models mirror rays past 90 degrees, so COLMAP is the oracle inside 89.9 degrees and the
closed-form law (written here from the formulas) beyond it. Points where pycolmap gives NaN or its
own round trip exceeds 1e-6 px are excluded and counted. COLMAP's pixel centres sit at i + 0.5,
as panoproj's: a spec's cx (OpenCV's convention) is COLMAP's cx - 0.5."""
import numpy as np
import pytest

import panoproj as pp

# (pycolmap 4.2 has no wheels for Python 3.9: the test extra leaves it out there)
pycolmap = pytest.importorskip("pycolmap")

N = 100_000


@pytest.fixture
def report():
    """Prints a figure line (seen with pytest -s)."""
    return lambda line: print("\n" + line)


def spec(name, fx, fy, cx, cy, fov=None, **keys):
    parts = [f"fx={fx!r}", f"fy={fy!r}", f"cx={cx - 0.5!r}", f"cy={cy - 0.5!r}"]
    if fov is not None:
        parts.insert(0, f"fov={fov!r}")
    parts += [f"{k}={v!r}" for k, v in keys.items()]
    return f"{name}:" + ",".join(parts)


# COLMAP model, its params, the frame, panoproj's spec, the largest ray angle sampled (deg), whether
# COLMAP's pixel -> ray is closed-form, and whether it is a fisheye model (mirrored past 90 deg).
def models():
    W, H = 1920, 1080
    f, cx, cy = 1000.0, 961.3, 538.7
    fx, fy = 1003.5, 998.2
    out = []

    def add(model, params, sp, theta_deg, closed, fisheye=False, size=(W, H), mirrored=False):
        out.append(pytest.param(dict(model=model, params=params, spec=sp, theta=theta_deg, closed=closed, fisheye=fisheye,
                                     mirrored=fisheye or mirrored, size=size), id=model))

    add("SIMPLE_PINHOLE", [f, cx, cy], spec("brown-conrady", f, f, cx, cy), 60, True)
    add("PINHOLE", [fx, fy, cx, cy], spec("brown-conrady", fx, fy, cx, cy), 60, True)
    add("SIMPLE_RADIAL", [f, cx, cy, -0.08], spec("brown-conrady", f, f, cx, cy, k1=-0.08), 55, False)
    add("RADIAL", [f, cx, cy, -0.08, 0.012], spec("brown-conrady", f, f, cx, cy, k1=-0.08, k2=0.012), 55, False)
    opencv = dict(k1=-0.21, k2=0.045, p1=0.0007, p2=-0.0004)
    add("OPENCV", [fx, fy, cx, cy, *opencv.values()], spec("brown-conrady", fx, fy, cx, cy, **opencv), 50, False)
    full = dict(k1=-0.19, k2=0.04, p1=0.0006, p2=-0.0003, k3=-0.002, k4=0.03, k5=0.006, k6=-0.001)
    add("FULL_OPENCV", [fx, fy, cx, cy, *full.values()], spec("brown-conrady", fx, fy, cx, cy, **full), 50, False)
    kb = dict(k1=0.0361, k2=-0.0112, k3=0.0028, k4=-0.0004)
    fe, fs = 620.5, (1920, 1920)
    add("OPENCV_FISHEYE", [fe, fe + 0.8, 959.2, 960.7, *kb.values()],
        spec("kannala-brandt", fe, fe + 0.8, 959.2, 960.7, fov=220, **kb), 110, False, True, fs)
    add("SIMPLE_RADIAL_FISHEYE", [fe, 959.2, 960.7, 0.03], spec("kannala-brandt", fe, fe, 959.2, 960.7, fov=220, k1=0.03),
        110, False, True, fs)
    add("RADIAL_FISHEYE", [fe, 959.2, 960.7, 0.03, -0.004],
        spec("kannala-brandt", fe, fe, 959.2, 960.7, fov=220, k1=0.03, k2=-0.004), 110, False, True, fs)
    tp = dict(k1=0.03, k2=-0.01, p1=0.0005, p2=-0.0004, k3=0.002, k4=-0.0003, sx1=0.0006, sy1=-0.0007)
    add("THIN_PRISM_FISHEYE", [fe, fe + 0.8, 959.2, 960.7, *tp.values()],
        spec("thin-prism-fisheye", fe, fe + 0.8, 959.2, 960.7, fov=220, **tp), 110, False, True, fs)
    rt = dict(k0=-0.0255, k1=0.0998, k2=-0.0697, k3=0.0132, k4=0.0034, k5=-0.0012, p0=0.0003, p1=-0.0002, s0=-0.0004,
              s1=0.0001, s2=0.0005, s3=-0.0001)
    add("RAD_TAN_THIN_PRISM_FISHEYE", [241.2, 241.3, 320.6, 240.9, *rt.values()],
        spec("rad-tan-thin-prism-fisheye", 241.2, 241.3, 320.6, 240.9, fov=190, **rt), 95, False, True, (640, 480))
    add("FOV", [fx, fy, cx, cy, 0.93], spec("devernay-faugeras", fx, fy, cx, cy, omega=0.93), 75, True)
    # A division fisheye past 90 degrees: COLMAP projects there (no cheirality test) but lifts a
    # pixel to its mirror, so its pixel -> ray is the oracle inside 89.9 degrees only (EUCM's too).
    add("SIMPLE_DIVISION", [400.0, cx, cy, -0.45], spec("division", 400.0, 400.0, cx, cy, fov=240, k=-0.45), 120, True,
        mirrored=True)
    add("DIVISION", [401.5, 399.2, cx, cy, -0.45], spec("division", 401.5, 399.2, cx, cy, fov=240, k=-0.45), 120, True,
        mirrored=True)
    add("SIMPLE_FISHEYE", [fe, 959.2, 960.7], spec("kannala-brandt", fe, fe, 959.2, 960.7, fov=220), 110, True, True, fs)
    add("FISHEYE", [fe, fe + 0.8, 959.2, 960.7], spec("kannala-brandt", fe, fe + 0.8, 959.2, 960.7, fov=220), 110, True,
        True, fs)
    add("EUCM", [fe, fe + 0.8, 959.2, 960.7, 0.63, 1.04],
        spec("extended-unified", fe, fe + 0.8, 959.2, 960.7, fov=200, alpha=0.63, beta=1.04), 100, True, False, fs,
        mirrored=True)  # COLMAP's EUCM lifts no pixel past 90 degrees (NaN)
    return out


def angle(a, b):
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.sum(a * b, axis=1))


def rays_within(theta_deg, n, seed):
    rng = np.random.default_rng(seed)
    z = 1 - (1 - np.cos(np.deg2rad(theta_deg))) * rng.random(n)  # uniform over the cap
    phi = rng.random(n) * 2 * np.pi
    s = np.sqrt(1 - z * z)
    return np.stack([s * np.cos(phi), s * np.sin(phi), z], -1)


def fisheye_law_pixels(m, rays, info):
    """COLMAP's fisheye models from their formulas (sensor/models.h), with theta = atan2(|xy|, z)
    where COLMAP takes atan(|xy| / z): the same below 90 degrees, the law's continuation past it."""
    p = m["params"]
    name = m["model"]
    if info.startswith("f,"):  # one focal length
        fx = fy = p[0]
        cx, cy, extra = p[1], p[2], p[3:]
    else:
        fx, fy, cx, cy, extra = p[0], p[1], p[2], p[3], p[4:]
    theta = np.arctan2(np.hypot(rays[:, 0], rays[:, 1]), rays[:, 2])
    phi = np.arctan2(rays[:, 1], rays[:, 0])
    u, v = theta * np.cos(phi), theta * np.sin(phi)
    t2 = u * u + v * v
    if name in ("SIMPLE_FISHEYE", "FISHEYE"):
        uu, vv = u, v
    elif name in ("SIMPLE_RADIAL_FISHEYE", "RADIAL_FISHEYE", "OPENCV_FISHEYE"):
        radial = sum(k * t2 ** (i + 1) for i, k in enumerate(extra))
        uu, vv = u * (1 + radial), v * (1 + radial)
    elif name == "THIN_PRISM_FISHEYE":
        k1, k2, p1, p2, k3, k4, sx1, sy1 = extra
        radial = k1 * t2 + k2 * t2**2 + k3 * t2**3 + k4 * t2**4
        uu = u * (1 + radial) + 2 * p1 * u * v + p2 * (t2 + 2 * u * u) + sx1 * t2
        vv = v * (1 + radial) + 2 * p2 * u * v + p1 * (t2 + 2 * v * v) + sy1 * t2
    else:  # RAD_TAN_THIN_PRISM_FISHEYE
        k, (p0, p1, s0, s1, s2, s3) = extra[:6], extra[6:]
        th = 1 + sum(ki * t2 ** (i + 1) for i, ki in enumerate(k))
        x, y = th * u, th * v
        r2 = x * x + y * y
        uu = x + 2 * p1 * x * y + p0 * (r2 + 2 * x * x) + s0 * r2 + s1 * r2 * r2
        vv = y + 2 * p0 * x * y + p1 * (r2 + 2 * y * y) + s2 * r2 + s3 * r2 * r2
    return np.stack([fx * uu + cx, fy * vv + cy], -1)


@pytest.mark.parametrize("m", models())
def test_rays_to_pixels_match_colmap(m, report):
    cam = pycolmap.Camera(model=m["model"], width=m["size"][0], height=m["size"][1], params=m["params"])
    rays = rays_within(m["theta"], N, seed=5)
    x, y, ok = pp.to_pixel(m["spec"], m["size"], rays)
    ours = np.stack([x, y], -1)
    inside = rays[:, 2] > np.cos(np.deg2rad(89.9)) if m["fisheye"] else np.ones(N, bool)
    theirs = cam.img_from_cam(rays, check_cheirality=False)
    back = cam.img_from_cam(cam.cam_ray_from_img(theirs), check_cheirality=False)
    # Where COLMAP lifts pixels to mirrored rays or none (past 90 degrees) its round trip cannot
    # be taken.
    liftable = rays[:, 2] > np.cos(np.deg2rad(89.9)) if m["mirrored"] else np.ones(N, bool)
    own = np.hypot(*(back - theirs).T)
    excluded = inside & (~np.isfinite(theirs).all(1) | (~(own <= 1e-6) & liftable))
    series = np.zeros(N, bool)
    if m["model"] == "FOV":
        # COLMAP's FOV distortion switches to a truncated Taylor series where |(x, y) / z|^2 < 1e-4
        # (models.h, "Chosen arbitrarily"): its error there is the next term, 1/5 (2 r tan(w/2))^4
        # of r. Those points are counted and held to that bound.
        series = inside & ~excluded & (np.sum((rays[:, :2] / rays[:, 2:3]) ** 2, 1) < 1e-4)
    use = ok & inside & ~excluded & ~series
    assert use.sum() > N // 10
    err = np.hypot(*(ours[use] - theirs[use]).T)
    line = f"{m['model']:27s} ray->pixel: {use.sum():6d} points, max {err.max():.2e} px vs pycolmap"
    assert err.max() < 1e-9, line
    if series.any():
        es = np.hypot(*(ours[series] - theirs[series]).T)
        r = np.sqrt(1e-4)
        bound = m["params"][0] * r * (2 * r * np.tan(m["params"][4] / 2)) ** 4 / 5 * 1.01
        line += f"; {series.sum()} points in COLMAP's series branch: max {es.max():.2e} px (its truncation: {bound:.2e})"
        assert es.max() <= bound, line
    if m["fisheye"]:  # past 89.9 degrees: the closed-form law
        past = ok & ~inside
        assert past.sum() > 100
        law = fisheye_law_pixels(m, rays[past], cam.params_info)
        e2 = np.hypot(*(ours[past] - law).T)
        line += f"; past 90 deg {past.sum()} points, max {e2.max():.2e} px vs the law"
        assert e2.max() < 1e-9, line
    report(line + f" ({excluded.sum()} excluded: pycolmap NaN or its round trip > 1e-6 px)")


@pytest.mark.parametrize("m", models())
def test_pixels_to_rays_match_colmap(m, report):
    cam = pycolmap.Camera(model=m["model"], width=m["size"][0], height=m["size"][1], params=m["params"])
    rng = np.random.default_rng(6)
    W, H = m["size"]
    px = np.stack([rng.random(N) * W, rng.random(N) * H], -1)
    ours, ok = pp.to_ray(m["spec"], m["size"], px[:, 0], px[:, 1])
    theirs = cam.cam_ray_from_img(px)
    nan = ~np.isfinite(theirs).all(1)
    back = cam.img_from_cam(np.where(nan[:, None], 1.0, theirs), check_cheirality=False)
    own = np.where(nan, np.inf, np.hypot(*(back - px).T))
    # Inside the sampled field (for fisheyes: inside 89.9 degrees, where COLMAP's ray is not mirrored).
    field = ok & (ours[:, 2] > np.cos(np.deg2rad(min(m["theta"], 89.9) if m["mirrored"] else m["theta"])))
    excluded = field & (nan | (own > 1e-6))
    use = field & ~excluded
    assert use.sum() > N // 10
    err = angle(ours[use], theirs[use])
    f = m["params"][0]
    own_max = own[use].max()
    line = (f"{m['model']:27s} pixel->ray: {use.sum():6d} points, max {err.max():.2e} rad ({err.max() * f:.2e} px); "
            f"pycolmap's own round trip {own_max:.2e} px ({excluded.sum()} excluded)")
    if m["closed"]:
        assert err.max() < 1e-9, line
    else:
        assert err.max() * f <= 10 * own_max + 1e-12, line
    report(line)


@pytest.fixture(scope="module")
def colmap_model(tmp_path_factory):
    """Every model above as a camera of one COLMAP model (and an EQUIRECTANGULAR one), written by
    pycolmap as text and as binary."""
    rec = pycolmap.Reconstruction()
    cams = {}
    # (EQUIRECTANGULAR's params are the panorama's w, h: a frame smaller is its top-left part.)
    panoramas = [pytest.param(dict(model="EQUIRECTANGULAR", params=[2048.0, 1024.0], size=(2048, 1024), closed=True,
                                   mirrored=False, theta=180), id="EQUIRECTANGULAR"),
                 pytest.param(dict(model="EQUIRECTANGULAR", params=[3000.0, 1600.0], size=(2048, 1024), closed=True,
                                   mirrored=False, theta=180), id="EQUIRECTANGULAR_PART")]
    for i, p in enumerate(models() + panoramas):
        m = p.values[0]
        cam = pycolmap.Camera(model=m["model"], width=m["size"][0], height=m["size"][1], params=m["params"])
        cam.camera_id = i + 1
        rec.add_camera(cam)
        cams[p.id] = (i + 1, m, cam)
    root = tmp_path_factory.mktemp("colmap")
    (root / "text").mkdir()
    (root / "binary").mkdir()
    rec.write_text(str(root / "text"))
    rec.write_binary(str(root / "binary"))
    return root, cams


@pytest.mark.parametrize("form", ["text", "binary"])
def test_colmap_cameras_files_are_specs(colmap_model, form, report):
    """@sparse/cameras.txt#ID (or cameras.bin): each camera's pixel -> ray against pycolmap's, as
    the spec written by hand is above."""
    root, cams = colmap_model
    name = "cameras.txt" if form == "text" else "cameras.bin"
    rng = np.random.default_rng(8)
    worst = {}
    for model, (cid, m, cam) in cams.items():
        W, H = m["size"]
        px = np.stack([rng.random(20_000) * W, rng.random(20_000) * H], -1)
        ours, ok = pp.to_ray(f"@{root / form / name}#{cid}", m["size"], px[:, 0], px[:, 1])
        theirs = cam.cam_ray_from_img(px)
        limit = min(m["theta"], 89.9) if m["mirrored"] else m["theta"]
        use = ok & np.isfinite(theirs).all(1) & (ours[:, 2] >= np.cos(np.deg2rad(limit)))
        assert use.sum() > 1000, model
        err = angle(ours[use], theirs[use])
        if m["closed"]:
            assert err.max() < 1e-9, (model, err.max())
        else:
            back = cam.img_from_cam(theirs[use], check_cheirality=False)
            own = np.hypot(*(back - px[use]).T).max()
            assert err.max() * m["params"][0] <= 10 * own + 1e-12, (model, err.max(), own)
        worst[model] = err.max()
    report(f"{name}: {len(cams)} cameras read as specs; pixel -> ray vs pycolmap, worst " +
           ", ".join(f"{k} {v:.1e}" for k, v in worst.items()) + " rad")
    # A camera's size is the calibrated one: an image of another size is refused.
    cid, m, _ = cams["OPENCV"]
    with pytest.raises(ValueError, match=r"the calibration is of 1920x1080 images, this frame is 960x540"):
        pp.to_ray(f"@{root / form / name}#{cid}", (960, 540), np.array([1.0]), np.array([1.0]))
    with pytest.raises(ValueError, match=r"holds cameras 1, 2, 3"):
        pp.projection(f"@{root / form / name}")
    with pytest.raises(ValueError, match=r"no camera 99 \(it holds 1, 2, 3"):
        pp.projection(f"@{root / form / name}#99")
