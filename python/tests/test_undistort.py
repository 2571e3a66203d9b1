"""`panoproj undistort` (Python's pp.undistort) against pycolmap 4.2's undistort_images (pip, a
test-only oracle) on models built here from known cameras, their images rendered from the bundled
panorama through the cameras' own specs (`--to @sparse/cameras.txt#ID`):
- cameras under max_fov: the same PINHOLE cameras (sizes equal, parameters within 1e-9 px) for
  blank_pixels 0 and 1 and a max_image_size, the observations moved alike (within 1e-6 px: COLMAP
  lifts by Newton to ~1e-8 px), and the images alike by PSNR where both have a source (both
  bilinear; the field's edge differs by a band of pixels: COLMAP blanks those whose taps leave the
  image);
- a 220-degree fisheye split into a rig of cube views that pycolmap.Reconstruction reads (rigs,
  frames, poses), whose observations are where pycolmap projects their points3D (1e-6 px), and on
  whose images and masks pycolmap.extract_features finds features;
- the same bytes from a Dask LocalCluster as from the local run."""
import hashlib
import pathlib
import subprocess

import numpy as np
import pytest

import panoproj as pp

# (pycolmap 4.2 has no wheels for Python 3.9: the test extra leaves it out there)
pycolmap = pytest.importorskip("pycolmap")

ROOT = pathlib.Path(__file__).resolve().parents[2]
PANO = str(ROOT / "samples" / "images" / "jordan_pond_4096x2048.jpg")

# COLMAP models both undistort into one pinhole (fields under 120 degrees).
PINHOLE_CAMERAS = [
    ("OPENCV", 640, 480, [500.0, 502.0, 320.4, 239.6, -0.2, 0.05, 0.001, -0.0005]),
    ("SIMPLE_RADIAL", 640, 480, [480.0, 319.5, 240.5, -0.1]),
    ("RADIAL", 600, 400, [450.0, 300.0, 200.0, -0.08, 0.01]),
    ("FULL_OPENCV", 640, 480, [500.0, 500.0, 321.0, 241.0, -0.19, 0.04, 0.0006, -0.0003, -0.002, 0.03, 0.006,
                               -0.001]),
    ("OPENCV_FISHEYE", 640, 480, [420.0, 420.5, 320.0, 240.0, 0.03, -0.01, 0.002, -0.0003]),
    ("PINHOLE", 500, 400, [400.0, 401.0, 250.5, 199.5]),
]


def build_model(root, cameras, cli, images_per_camera=1, points=None, seed=3, pitch=0):
    """A model of `cameras` (one rig each, a frame per image), its images rendered from PANO through
    each camera's spec, random observations (or `points`: world points seen within 85 degrees)."""
    rng = np.random.default_rng(seed)
    rec = pycolmap.Reconstruction()
    cams = []
    for c, (model, w, h, params) in enumerate(cameras, start=1):
        cam = pycolmap.Camera.create_from_model_name(c, model, 1.0, w, h)
        cam.params = params
        rec.add_camera(cam)
        cams.append(cam)
        rig = pycolmap.Rig(rig_id=c)
        rig.add_ref_sensor(cam.sensor_id)
        rec.add_rig(rig)
    image_id, tracks = 0, [[] for _ in range(0 if points is None else len(points))]
    for c, cam in enumerate(cams, start=1):
        for k in range(images_per_camera):
            image_id += 1
            pose = pycolmap.Rigid3d(pycolmap.Rotation3d(rng.normal(0, 0.3, 3)), rng.normal(0, 1, 3))
            if points is None:
                xy = list(rng.uniform([2, 2], [cam.width - 2, cam.height - 2], (40, 2)))
            else:
                xy = seen(cam, pose, points, image_id, tracks)
            frame = pycolmap.Frame()
            frame.frame_id, frame.rig_id, frame.rig_from_world = image_id, c, pose
            im = pycolmap.Image(name=f"cam{c}/img{k}.png", camera_id=c, image_id=image_id)
            im.frame_id = image_id
            im.points2D = pycolmap.Point2DList([pycolmap.Point2D(p) for p in xy])
            frame.add_data_id(im.data_id)
            rec.add_frame(frame)
            rec.add_image(im)
            rec.register_frame(image_id)
    for p, track in zip([] if points is None else points, tracks):
        if len(track) >= 2:
            t = pycolmap.Track()
            for i, k in track:
                t.add_element(i, k)
            rec.add_point3D(p, t)
    sparse = root / "sparse"
    sparse.mkdir(parents=True)
    rec.write_text(str(sparse))
    for im in rec.images.values():
        (root / "images" / im.name).parent.mkdir(parents=True, exist_ok=True)
        subprocess.run([cli, "convert", PANO, str(root / "images" / im.name), "--to",
                        f"@{sparse}/cameras.txt#{im.camera_id}", "--yaw", str(37 * im.image_id), "--pitch", str(pitch),
                        "-q"], check=True)
    return rec


def seen(cam, cam_from_world, points, image_id, tracks):
    """The pixels of the points pycolmap projects into the image within 85 degrees of its axis; each
    added to its point's track."""
    xys = []
    for n, p in enumerate(points):
        pc = cam_from_world * p
        if np.degrees(np.arctan2(np.hypot(pc[0], pc[1]), pc[2])) > 85:
            continue
        xy = cam.img_from_cam(pc)
        if xy is not None and 0 <= xy[0] < cam.width and 0 <= xy[1] < cam.height:
            tracks[n].append((image_id, len(xys)))
            xys.append(xy)
    return xys


def psnr(a, b):
    mse = np.mean((a.astype(np.float64) - b.astype(np.float64)) ** 2)
    return 10 * np.log10(255.0 ** 2 / mse) if mse > 0 else np.inf


@pytest.fixture(scope="module")
def pinhole_model(tmp_path_factory, cli):
    root = tmp_path_factory.mktemp("undistort")
    build_model(root, PINHOLE_CAMERAS, cli)
    return root


# (id, COLMAP's UndistortCameraOptions, panoproj's arguments)
OPTIONS = [
    ("crop", {}, {}),
    ("keep_all", dict(blank_pixels=1.0), dict(blank_pixels=1.0)),
    ("half_max500", dict(blank_pixels=0.5, max_image_size=500), dict(blank_pixels=0.5, max_image_size=500)),
    ("roi", dict(roi_min_x=0.1, roi_min_y=0.05, roi_max_x=0.8, roi_max_y=0.9, blank_pixels=0.3),
     dict(roi="0.1,0.05,0.8,0.9", blank_pixels=0.3)),
    ("scales", dict(min_scale=0.9, max_scale=1.05, blank_pixels=1.0),
     dict(min_scale=0.9, max_scale=1.05, blank_pixels=1.0)),
]


@pytest.mark.parametrize("theirs_kw, ours_kw", [o[1:] for o in OPTIONS], ids=[o[0] for o in OPTIONS])
def test_pinholes_match_pycolmap(pinhole_model, tmp_path, theirs_kw, ours_kw, report):
    compare_with_pycolmap(pinhole_model, tmp_path, theirs_kw, ours_kw, report, PINHOLE_CAMERAS)


# A 152-degree fisheye undistorted into one pinhole anyway (max_fov raised), its frame's edge cut
# where tan(theta) passes max_cam_point_norm, as COLMAP does.
WIDE = [("OPENCV_FISHEYE", 640, 480, [300.0, 300.5, 321.0, 238.0, 0.03, -0.01, 0.002, -0.0003])]


@pytest.mark.parametrize("norm", [0, 2.5, 1.6])
def test_a_wide_fisheye_as_one_pinhole_matches_pycolmap(tmp_path, cli, norm, report):
    build_model(tmp_path / "model", WIDE, cli)
    theirs = dict(max_cam_point_norm=norm) if norm else {}
    compare_with_pycolmap(tmp_path / "model", tmp_path, theirs, dict(max_fov=170, max_cam_point_norm=norm),
                          report, WIDE)


def compare_with_pycolmap(model, tmp_path, theirs_kw, ours_kw, report, cameras):
    pinhole_model = model
    options = pycolmap.UndistortCameraOptions()
    for k, v in theirs_kw.items():
        setattr(options, k, v)
    pycolmap.undistort_images(str(tmp_path / "colmap"), str(pinhole_model / "sparse"), str(pinhole_model / "images"),
                              undistort_options=options)
    r = pp.undistort(str(pinhole_model / "sparse"), str(pinhole_model / "images"), str(tmp_path / "ours"),
                     interp="bilinear", **ours_kw)
    assert all(c["pinhole"] for c in r["cameras"])
    theirs = pycolmap.Reconstruction(str(tmp_path / "colmap" / "sparse"))
    ours = pycolmap.Reconstruction(str(tmp_path / "ours" / "sparse"))
    assert sorted(theirs.cameras) == sorted(ours.cameras)
    worst_param = worst_point = 0.0
    lines = []
    for i, c in theirs.cameras.items():
        d = ours.cameras[i]
        assert d.model == pycolmap.CameraModelId.PINHOLE and (d.width, d.height) == (c.width, c.height)
        worst_param = max(worst_param, np.abs(np.array(d.params) - np.array(c.params)).max())
    for i, im in theirs.images.items():
        jm = ours.images[i]
        assert jm.name == im.name and jm.camera_id == im.camera_id
        assert np.abs(jm.cam_from_world().matrix() - im.cam_from_world().matrix()).max() <= 1e-12
        a = np.array([p.xy for p in im.points2D])
        b = np.array([p.xy for p in jm.points2D])
        assert a.shape == b.shape == (40, 2)
        worst_point = max(worst_point, np.abs(a - b).max())
        x, y = pp.read(str(tmp_path / "colmap" / "images" / im.name)), pp.read(str(tmp_path / "ours" / "images" / im.name))
        assert x.shape == y.shape
        # Where both have a source (COLMAP blanks a pixel whose 2x2 taps leave the image; panoproj
        # samples every pixel whose centre maps inside it, taps clamped): a band of edge pixels.
        fx, fy = x.max(axis=2) > 0, y.max(axis=2) > 0
        q = psnr(x[fx & fy], y[fx & fy])
        edge = (fx ^ fy).mean()
        cam = theirs.cameras[im.camera_id]
        lines.append(f"{cameras[im.camera_id - 1][0]} {cam.width}x{cam.height}: PSNR {q:.1f} dB, "
                     f"{100 * edge:.2f}% edge pixels only one has")
        assert q > 38 and edge < 0.01, lines[-1]
    report(f"undistort {ours_kw}: params within {worst_param:.1e} px, "
           f"points2D within {worst_point:.1e} px; " + "; ".join(lines))
    assert worst_param <= 1e-9 and worst_point <= 1e-6


@pytest.fixture
def report():
    return lambda line: print("\n" + line)


# A full-frame 220-degree fisheye: its frame's corners 110 degrees off axis (theta_d(110 deg) = 1.9515, 724 px = 1.9515 f).
FISHEYE_220 = ("OPENCV_FISHEYE", 1024, 1024, [371.0, 371.0, 511.5, 512.5, 0.012, -0.004, 0.0009, -0.0001])


@pytest.fixture(scope="module")
def fisheye_model(tmp_path_factory, cli):
    root = tmp_path_factory.mktemp("fisheye")
    rng = np.random.default_rng(11)
    xyz = rng.normal(0, 1, (300, 3))
    xyz = 8 * xyz / np.linalg.norm(xyz, axis=1, keepdims=True)
    rec = build_model(root, [FISHEYE_220], cli, images_per_camera=3, points=xyz, pitch=-60)  # (up: the shore)
    return root, rec


def test_220_degree_fisheye_into_a_rig_colmap_reads(fisheye_model, tmp_path, report):
    root, rec = fisheye_model
    r = pp.undistort(str(root / "sparse"), str(root / "images"), str(tmp_path / "out"), size=(400, 400))
    (cam,) = r["cameras"]
    assert not cam["pinhole"] and 218 < cam["field"] < 222, cam["field"]
    assert cam["views"] == ["front", "right", "left", "up", "down"]  # (back sees none of it)
    out = pycolmap.Reconstruction(str(tmp_path / "out" / "sparse"))
    assert out.num_rigs() == 1 and out.num_frames() == 3 and out.num_images() == 15
    (rig,) = out.rigs.values()
    assert rig.num_sensors() == 5
    # Each moved observation is where pycolmap projects its point3D in the view.
    worst, seen, checked = 0.0, 0, 0
    for im in out.images.values():
        c = out.cameras[im.camera_id]
        for p in im.points2D:
            assert 0 <= p.xy[0] < c.width and 0 <= p.xy[1] < c.height
            seen += 1
            if p.has_point3D():
                xy = c.img_from_cam(im.cam_from_world() * out.points3D[p.point3D_id].xyz)
                worst, checked = max(worst, np.abs(xy - p.xy).max()), checked + 1
    kept = sum(len(im.points2D) for im in rec.images.values())
    assert out.num_points3D() == rec.num_points3D()
    report(f"220-degree fisheye -> 5 cube views x 3 frames: {seen} of {kept} observations kept "
           f"(each falls in a view); {checked} of them, of {out.num_points3D()} points3D, where pycolmap "
           f"projects their point within {worst:.1e} px")
    assert seen == kept and checked > 100 and worst <= 1e-6
    # pycolmap extracts features from the views, with their masks.
    db = tmp_path / "db.db"
    reader = pycolmap.ImageReaderOptions()
    reader.mask_path = str(tmp_path / "out" / "masks")
    pycolmap.extract_features(str(db), str(tmp_path / "out" / "images"), reader_options=reader,
                              camera_mode=pycolmap.CameraMode.PER_FOLDER)
    with pycolmap.Database.open(str(db)) as d:
        counts = {d.read_image(i).name: d.read_keypoints(i).shape[0] for i in range(1, d.num_images() + 1)}
    report("features per view: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())))
    assert len(counts) == 15 and min(counts.values()) > 50


def test_dask_gives_the_local_bytes(pinhole_model, tmp_path):
    from dask.distributed import Client, LocalCluster

    def digests(folder):
        return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
                for p in sorted(pathlib.Path(folder).rglob("*")) if p.is_file()}

    args = (str(pinhole_model / "sparse"), str(pinhole_model / "images"))
    pp.undistort(*args, str(tmp_path / "local"))
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        pp.undistort(*args, str(tmp_path / "dask"), client=client)
    assert digests(tmp_path / "dask") == digests(tmp_path / "local")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dask", "local"]
