"""pp.views: every written camera checked through an independent reader against the panorama.

The projection check: for 1000 random directions inside a view, the pixel the written camera
gives (pycolmap 4.2 reading sparse/0, or nerfstudio's ray convention reading transforms.json),
sampled in the written view image, against the panorama sampled at that direction. On a smooth
source with more than 5 LSB of change per degree the mean absolute difference must stay under
2 LSB, and a 1-degree heading error or a swapped face must push it over (both asserted here)."""
import hashlib
import json
import math
import pathlib

import numpy as np
import pytest

import panoproj as pp

# (pycolmap 4.2 has no wheels for Python 3.9: the test extra leaves it out there)
pycolmap = pytest.importorskip("pycolmap")

W, H = 2048, 1024
N = 1000
# Three waves on the sphere (unit normals, phases): 127.5 + 110 sin(12 n.d + phi) per channel.
WAVES = [((0.6, 0.48, 0.64), 0.3), ((-0.36, 0.8, 0.48), 1.9), ((0.0, -0.6, 0.8), 4.1)]


def field(d, shift=0.0):
    """The scene at unit directions d (..., 3) in panoproj's frame (x right, y down, z forward)."""
    return np.stack([127.5 + 110 * np.sin(12 * (d @ np.array(n)) + p + shift) for n, p in WAVES], axis=-1)


def equirect_directions(w, h):
    lon = (np.arange(w) + 0.5) / w * 2 * np.pi - np.pi
    lat = np.pi / 2 - (np.arange(h) + 0.5) / h * np.pi
    lon, lat = np.meshgrid(lon, lat)
    return np.stack([np.cos(lat) * np.sin(lon), -np.sin(lat), np.cos(lat) * np.cos(lon)], axis=-1)


def bilinear(img, u, v, wrap=False):
    """img at continuous pixel coordinates (u, v), the top-left pixel's centre at (0.5, 0.5)."""
    h, w = img.shape[:2]
    x, y = u - 0.5, np.clip(v - 0.5, 0, h - 1)
    x0, y0 = np.floor(x).astype(int), np.minimum(np.floor(y).astype(int), h - 2)
    fx, fy = (x - x0)[:, None], (y - y0)[:, None]
    x1 = x0 + 1
    if wrap:
        x0, x1 = x0 % w, x1 % w
    else:
        x0, x1 = np.clip(x0, 0, w - 1), np.clip(x1, 0, w - 1)
    im = img.astype(np.float64)
    return ((im[y0, x0] * (1 - fx) + im[y0, x1] * fx) * (1 - fy) + (im[y0 + 1, x0] * (1 - fx) + im[y0 + 1, x1] * fx) * fy)


def panorama_at(pano, d):
    lon, lat = np.arctan2(d[:, 0], d[:, 2]), np.arcsin(np.clip(-d[:, 1], -1, 1))
    h, w = pano.shape[:2]
    return bilinear(pano, (lon + np.pi) / (2 * np.pi) * w, (np.pi / 2 - lat) / np.pi * h, wrap=True)


def yaw_rotation(deg):
    a = math.radians(deg)
    return np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])


@pytest.fixture(scope="module")
def smooth(tmp_path_factory):
    folder = tmp_path_factory.mktemp("views")
    img = np.clip(np.round(field(equirect_directions(W, H))), 0, 255).astype(np.uint8)
    pp.write(str(folder / "pano.png"), img)
    return folder / "pano.png", img


def test_the_source_changes_by_more_than_5_lsb_a_degree():
    rng = np.random.default_rng(1)
    d = rng.normal(size=(20000, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    t = np.cross(d, rng.normal(size=(20000, 3)))
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    a = math.radians(1)
    moved = d * math.cos(a) + t * math.sin(a)
    assert np.mean(np.abs(field(moved) - field(d))) > 5  # mean over channels and random ways


def directions_in_view(project, size, rng, n=N):
    """n random directions (uniform on the sphere) whose pixel is inside the view by a pixel."""
    found = []
    while sum(len(f) for f in found) < n:
        d = rng.normal(size=(200000, 3))
        d /= np.linalg.norm(d, axis=1, keepdims=True)
        uv = project(d)
        ok = np.isfinite(uv).all(axis=1)
        ok[ok] &= (uv[ok, 0] > 1) & (uv[ok, 0] < size[0] - 1) & (uv[ok, 1] > 1) & (uv[ok, 1] < size[1] - 1)
        found.append(d[ok])
    return np.concatenate(found)[:n]


def colmap_error(rec, image, folder, pano, cam_from_world, rng):
    """Mean |view(pixel of d) - pano(d)| over 1000 directions d inside the view, the pixel given by
    pycolmap's camera and the rotation cam_from_world (3x3, world = the panorama's frame)."""
    cam = rec.cameras[image.camera_id]

    def project(d):
        pc = d @ cam_from_world.T
        uv = np.full((len(d), 2), np.nan)
        front = pc[:, 2] > 1e-6
        uv[front] = cam.img_from_cam(pc[front])
        return uv

    d = directions_in_view(project, (cam.width, cam.height), rng)
    view = pp.read(str(folder / "images" / image.name))
    uv = project(d)
    return float(np.mean(np.abs(bilinear(view, uv[:, 0], uv[:, 1]) - panorama_at(pano, d))))


@pytest.mark.parametrize("rig", ["cube", "ring:n=5,fov=80,vfov=60,pitch=-25,yaw=10",
                                 "- {name: tilted, yaw: -35, pitch: 20, roll: 15, hfov: 70, size: 640x400}\n"
                                 "- {name: wide, yaw: 150, pitch: -60, hfov: 120, vfov: 90}"])
def test_written_colmap_cameras_sample_the_panorama_where_it_is(smooth, tmp_path, rig):
    path, pano = smooth
    out = tmp_path / "out"
    report = pp.views(path, out, rig=rig, format="png")
    rec = pycolmap.Reconstruction(str(out / "sparse" / "0"))
    assert rec.num_images() == len(report["views"]) and rec.num_frames() == 1 and len(rec.rigs) == 1
    rng = np.random.default_rng(7)
    errors = {}
    for image in sorted(rec.images.values(), key=lambda i: i.image_id):
        view = image.name[len("pano_"):-len(".png")]
        r = image.cam_from_world().rotation.matrix()
        cam = rec.cameras[image.camera_id]
        # COLMAP's pixel convention: the principal point is the image's centre, W/2 and H/2.
        assert cam.model.name == "PINHOLE"
        assert cam.principal_point_x == cam.width / 2 and cam.principal_point_y == cam.height / 2
        good = colmap_error(rec, image, out, pano, r, rng)
        late = colmap_error(rec, image, out, pano, r @ yaw_rotation(1.0), rng)
        errors[view] = (good, late)
        assert good < 2, f"{view}: mean difference {good:.2f} LSB"
        if view not in ("up", "down"):  # (a heading error turns those about their own axis)
            assert late > 2, f"{view}: a 1-degree heading error gives only {late:.2f} LSB"
    if rig == "cube":
        # A swapped face: front's image with right's rotation, and the other way round.
        images = {i.name: i for i in rec.images.values()}
        front, right = images["pano_front.png"], images["pano_right.png"]
        swapped = colmap_error(rec, front, out, pano, right.cam_from_world().rotation.matrix(), rng)
        assert swapped > 20
        assert max(e[1] for v, e in errors.items() if v in ("up", "down")) > 2  # they fail too, less
    print(rig.split("\n")[0], {k: (round(a, 3), round(b, 2)) for k, (a, b) in errors.items()})


@pytest.mark.parametrize("rig", ["cube", "ring:n=5,fov=80,vfov=60,pitch=-25,yaw=10",
                                 "- {name: tilted, yaw: -35, pitch: 20, roll: 15, hfov: 70, size: 640x400}\n"
                                 "- {name: wide, yaw: 150, pitch: -60, hfov: 120, vfov: 90}"])
def test_views_through_colmaps_equirectangular_camera(smooth, tmp_path, rig):
    """A panorama pixel's ray by COLMAP 4's EQUIRECTANGULAR camera (sensor/models/spherical.h: what
    panorama_sfm.py --convert_to_equirectangular uses), taken into each view by the written model
    (the image's cam_from_world, and the rig's sensor_from_rig with the frame's rig_from_world),
    equals panoproj's ray of that pixel turned into the view (the report's world_from_camera),
    within 1e-9 rad."""
    path, pano = smooth
    report = pp.views(path, tmp_path / "out", rig=rig, format="png")
    rec = pycolmap.Reconstruction(str(tmp_path / "out" / "sparse" / "0"))
    equirect = pycolmap.Camera.create_from_model_name(1, "EQUIRECTANGULAR", 1.0, W, H)
    rng = np.random.default_rng(13)
    x, y = rng.uniform(0, W, 20_000), rng.uniform(0, H, 20_000)
    x[:4], y[:4] = [0.5, W - 0.5, 0.5, W / 2], [0.5, H - 0.5, H / 2, 0.5]  # (rims and the poles' rows)
    rays, ok = pp.to_ray("equirect", (W, H), x, y)
    assert ok.all()
    theirs = np.array([equirect.cam_ray_from_img(np.array([u, v])) for u, v in zip(x, y)])
    theirs /= np.linalg.norm(theirs, axis=1, keepdims=True)
    (frame,) = rec.frames.values()
    (rig_model,) = rec.rigs.values()
    worst = 0.0
    views = {v["name"]: np.array(v["world_from_camera"]) for v in report["views"]}
    for image in rec.images.values():
        view = image.name[len("pano_"):-len(".png")]
        ours = rays @ views[view]  # (R^T ray per row)
        by_image = theirs @ image.cam_from_world().rotation.matrix().T
        sensor = rig_model.sensor_from_rig(image.data_id.sensor_id) if image.data_id.sensor_id != rig_model.ref_sensor_id \
            else pycolmap.Rigid3d()
        cam_from_world = sensor.rotation.matrix() @ frame.rig_from_world.rotation.matrix()
        by_rig = theirs @ cam_from_world.T
        for b in (by_image, by_rig):
            # (atan2 of the cross and dot products: arccos loses digits near 0)
            worst = max(worst, np.arctan2(np.linalg.norm(np.cross(ours, b), axis=1), np.sum(ours * b, axis=1)).max())
    print(f"\n{rig.splitlines()[0]}: {len(report['views'])} views x {len(x)} panorama pixels, "
          f"COLMAP's EQUIRECTANGULAR within {worst:.1e} rad")
    assert worst <= 1e-9


def images_txt_poses(path):
    """NAME -> (quaternion w x y z, translation) read from images.txt as other readers do."""
    lines = [l for l in pathlib.Path(path).read_text().splitlines() if l and not l.startswith("#")]
    return {l.split()[9]: (np.array(l.split()[1:5], float), np.array(l.split()[5:8], float)) for l in lines}


def test_a_sequence_is_one_rig_with_a_frame_per_panorama(smooth, tmp_path):
    path, pano = smooth
    frames = []
    for k in range(3):
        p = tmp_path / f"frame{k:03d}.jpg"
        pp.write(str(p), pano, quality=95)
        frames.append(p)
    out = tmp_path / "out"
    report = pp.views(frames, out, rig="cube", size=(256, 256))
    assert report["frames"] == ["frame000", "frame001", "frame002"] and report["images"] == 18
    rec = pycolmap.Reconstruction(str(out / "sparse" / "0"))
    assert rec.num_frames() == 3 and rec.num_images() == 18 and len(rec.cameras) == 6
    (rig,) = rec.rigs.values()
    assert rig.num_sensors() == 6
    poses = images_txt_poses(out / "sparse" / "0" / "images.txt")
    names = [v["name"] for v in report["views"]]
    for frame in rec.frames.values():
        assert len(frame.data_ids) == 6
        for data in frame.data_ids:
            image = rec.images[data.id]
            # the image's pose through the rig equals images.txt's and the report's rotation
            r = image.cam_from_world().rotation.matrix()
            q, t = poses[image.name]
            quat = pycolmap.Rotation3d(np.array([q[1], q[2], q[3], q[0]])).matrix()
            assert np.allclose(r, quat, atol=1e-12) and not t.any()
            view = report["views"][names.index(image.name.split("_", 1)[1][:-4])]
            assert np.allclose(r, np.array(view["world_from_camera"]).T, atol=1e-12)
            assert image.camera_id == data.sensor_id.id
    # pycolmap writes back what it read: the same numbers
    (tmp_path / "again").mkdir()
    rec.write_text(str(tmp_path / "again"))
    for name in ("cameras.txt", "images.txt", "rigs.txt", "frames.txt"):
        ours = [l for l in (out / "sparse" / "0" / name).read_text().splitlines() if l and not l.startswith("#")]
        theirs = [l for l in (tmp_path / "again" / name).read_text().splitlines() if l and not l.startswith("#")]
        assert len(ours) == len(theirs)
        for a, b in zip(ours, theirs):
            for x, y in zip(a.split(), b.split()):
                try:
                    assert float(x) == pytest.approx(float(y), abs=1e-9)
                except ValueError:
                    assert x == y


def nerfstudio_error(frame, intrinsics, folder, pano, rng, turn=np.eye(3)):
    """The projection check through transforms.json, by nerfstudio's convention (cameras.py,
    generate_rays): pixel (u, v) with pixel i's centre at i + 0.5 looks along
    c2w[:3, :3] @ [(u - cx) / fl_x, -(v - cy) / fl_y, -1]; the world here is z up."""
    c2w = np.array(frame["transform_matrix"])[:3, :3] @ turn
    fx, fy, cx, cy = (intrinsics[k] for k in ("fl_x", "fl_y", "cx", "cy"))
    from_z_up = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]])  # (x, y, z)_z-up -> panoproj (x, -z, y)

    def project(d):
        c = (d @ from_z_up) @ c2w  # world_z_up = from_z_up^T d ; camera = c2w^T world
        uv = np.full((len(d), 2), np.nan)
        front = c[:, 2] < -1e-6
        uv[front, 0] = cx + fx * c[front, 0] / -c[front, 2]
        uv[front, 1] = cy - fy * c[front, 1] / -c[front, 2]
        return uv

    d = directions_in_view(project, (intrinsics["w"], intrinsics["h"]), rng)
    uv = project(d)
    view = pp.read(str(folder / frame["file_path"]))
    return float(np.mean(np.abs(bilinear(view, uv[:, 0], uv[:, 1]) - panorama_at(pano, d))))


@pytest.mark.parametrize("rig", ["cube", "- {name: a, yaw: 30, pitch: 10, roll: -20, hfov: 75, size: 500x300}\n"
                                         "- {name: b, yaw: -120, pitch: -40, hfov: 100}"])
def test_transforms_json_follows_nerfstudios_convention(smooth, tmp_path, rig):
    path, pano = smooth
    out = tmp_path / "out"
    pp.views(path, out, rig=rig, format="png")
    meta = json.loads((out / "transforms.json").read_text())
    assert meta["camera_model"] == "OPENCV"
    rng = np.random.default_rng(3)
    for frame in meta["frames"]:
        intrinsics = frame if "fl_x" in frame else meta
        assert intrinsics["cx"] == intrinsics["w"] / 2 and intrinsics["cy"] == intrinsics["h"] / 2
        good = nerfstudio_error(frame, intrinsics, out, pano, rng)
        assert good < 2, f"{frame['file_path']}: {good:.2f} LSB"
        up = np.array(frame["transform_matrix"])[:3, 1]
        if abs(up[2]) > 0.5:  # a side view: a heading error must show
            turn = np.array(frame["transform_matrix"])[:3, :3].T @ _z_turn(1.0) @ np.array(frame["transform_matrix"])[:3, :3]
            assert nerfstudio_error(frame, intrinsics, out, pano, rng, turn) > 2
    if rig == "cube":
        swapped = dict(meta["frames"][0], file_path=meta["frames"][1]["file_path"])
        assert nerfstudio_error(swapped, meta, out, pano, rng) > 20


def _z_turn(deg):
    a = math.radians(deg)
    return np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])


def test_a_partial_panorama_gets_masks_where_the_view_leaves_it(smooth, tmp_path):
    path, pano = smooth
    part = tmp_path / "part.png"
    pp.write(str(part), pano[256:768, 512:1536])  # 180 x 90 degrees about the centre
    out = tmp_path / "out"
    report = pp.views(part, out, rig="ring:n=4,fov=90", src="equirect:hfov=180,vfov=90", format="png")
    assert report["masks"]
    meta = json.loads((out / "transforms.json").read_text())
    rng = np.random.default_rng(11)
    for frame in meta["frames"]:
        mask = pp.read(str(out / frame["mask_path"]))
        assert mask.dtype == np.uint8 and set(np.unique(mask)) <= {0, 255}
        view = pp.read(str(out / frame["file_path"]))
        c2w = np.array(frame["transform_matrix"])[:3, :3]
        w, h, f = meta["w"], meta["h"], meta["fl_x"]
        u, v = rng.uniform(0, w, 4000), rng.uniform(0, h, 4000)
        z_up = np.stack([(u - w / 2) / f, -(v - h / 2) / f, -np.ones_like(u)], axis=1) @ c2w.T
        d = np.stack([z_up[:, 0], -z_up[:, 2], z_up[:, 1]], axis=1)  # panoproj's frame
        d /= np.linalg.norm(d, axis=1, keepdims=True)
        lon, lat = np.degrees(np.arctan2(d[:, 0], d[:, 2])), np.degrees(np.arcsin(-d[:, 1]))
        inside = (np.abs(lon) < 89) & (np.abs(lat) < 44)
        outside = (np.abs(lon) > 91) | (np.abs(lat) > 46)
        m = mask[v.astype(int), u.astype(int)]
        assert (m[inside] == 255).all() and (m[outside] == 0).all()
        assert (view[v.astype(int), u.astype(int)][outside] == 0).all()  # flattened over black
    names = sorted(p.name for p in (out / "masks").iterdir())
    assert names == sorted(pathlib.Path(f["file_path"]).name + ".png" for f in meta["frames"])


def digests(folder):
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(pathlib.Path(folder).rglob("*")) if p.is_file()}


def test_views_on_a_local_cluster_equal_the_local_run(smooth, tmp_path):
    from dask.distributed import Client, LocalCluster

    path, pano = smooth
    frames = []
    for k in range(4):
        p = tmp_path / f"seq_{k}.jpg"
        pp.write(str(p), np.roll(pano, 37 * k, axis=1), quality=90)
        frames.append(p)
    local = pp.views(frames, tmp_path / "local", rig="cube+ring:n=3,pitch=45", size=(300, 200))
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        remote = pp.views(frames, tmp_path / "dask", rig="cube+ring:n=3,pitch=45", size=(300, 200), client=client,
                          threads=1)
    assert remote["tasks"] == 4 and remote["images"] == local["images"] == 4 * 9
    assert digests(tmp_path / "dask") == digests(tmp_path / "local")
    assert len(digests(tmp_path / "local")) == 36 + 6 + 1  # images, camera files, the marker
    assert sorted(p.name for p in tmp_path.iterdir() if p.is_dir()) == ["dask", "local"]  # no temporary left


def _rotation_angle(r):
    return math.degrees(math.acos(np.clip((np.trace(r) - 1) / 2, -1, 1)))


def test_colmaps_rig_configurator_and_sift_agree_with_the_written_rig(tmp_path):
    """layout="folders" on a real photo (the bundled Jordan Pond): COLMAP's own feature extraction,
    rig configuration and matching (pycolmap 4.2) take the views and rig_config.json; the rig it
    builds holds the written rotations and intrinsics, and the rotation between overlapping views
    fitted to SIFT matches (rays by the written intrinsics) is the written one."""
    sample = pathlib.Path(__file__).resolve().parents[2] / "samples" / "images" / "jordan_pond_4096x2048.jpg"
    frames = []
    for k in range(2):
        (tmp_path / f"f{k}.jpg").write_bytes(sample.read_bytes())
        frames.append(tmp_path / f"f{k}.jpg")
    out = tmp_path / "out"
    report = pp.views(frames, out, rig="ring:n=8,fov=90,pitch=10", size=(480, 360), layout="folders")
    names = [v["name"] for v in report["views"]]
    assert sorted(p.name for p in (out / "images").iterdir()) == sorted(names)
    db_path = str(tmp_path / "database.db")
    reader = pycolmap.ImageReaderOptions()
    reader.camera_model = "PINHOLE"
    extraction = pycolmap.FeatureExtractionOptions()
    extraction.num_threads = 2
    pycolmap.extract_features(db_path, str(out / "images"), camera_mode=pycolmap.CameraMode.PER_FOLDER,
                              reader_options=reader, extraction_options=extraction, device=pycolmap.Device.cpu)
    db = pycolmap.Database.open(db_path)
    pycolmap.apply_rig_config(pycolmap.read_rig_config(str(out / "rig_config.json")), db)
    (rig,) = db.read_all_rigs()
    frames_db = db.read_all_frames()
    images = {i.image_id: i for i in db.read_all_images()}
    cameras = {c.camera_id: c for c in db.read_all_cameras()}
    assert rig.num_sensors() == 8 and len(frames_db) == 2
    world_from = {v["name"]: np.array(v["world_from_camera"]) for v in report["views"]}
    ref = next(i for i in images.values() if i.camera_id == rig.ref_sensor_id.id).name.split("/")[0]
    assert ref == names[0]
    for frame in frames_db:
        stems = {images[d.id].name.split("/")[1] for d in frame.data_ids}
        assert len(frame.data_ids) == 8 and len(stems) == 1  # one panorama per frame
    for image in images.values():
        view = image.name.split("/")[0]
        cam = cameras[image.camera_id]
        assert cam.model.name == "PINHOLE" and list(cam.params) == pytest.approx(
            [report["views"][0]["focal"]] * 2 + [240, 180], abs=1e-9)
        if image.camera_id != rig.ref_sensor_id.id:
            sensor = pycolmap.sensor_t(pycolmap.SensorType.CAMERA, image.camera_id)
            got = rig.sensor_from_rig(sensor).rotation.matrix()
            assert np.allclose(got, world_from[view].T @ world_from[ref], atol=1e-9)
    db.close()
    pycolmap.match_exhaustive(db_path, device=pycolmap.Device.cpu)
    db = pycolmap.Database.open(db_path)
    by_name = {i.name: i for i in db.read_all_images()}
    fits = []
    for a, b in zip(names, names[1:] + names[:1]):  # neighbours overlap by 45 degrees
        ia, ib = by_name[f"{a}/f0.jpg"], by_name[f"{b}/f0.jpg"]
        tvg = db.read_two_view_geometry(ia.image_id, ib.image_id)
        pairs = tvg.inlier_matches  # (keypoint in ia, keypoint in ib), as asked
        assert len(pairs) > 30, (a, b, len(pairs))

        def rays(image, idx):
            xy = db.read_keypoints(image.image_id)[idx, :2]
            r = np.column_stack([cameras[image.camera_id].cam_from_img(xy), np.ones(len(xy))])
            return r / np.linalg.norm(r, axis=1, keepdims=True)

        ra, rb = rays(ia, pairs[:, 0]), rays(ib, pairs[:, 1])
        keep = np.ones(len(ra), bool)
        for _ in range(10):  # Kabsch (rb ~ R ra), refitted to the matches within 3 median residuals
            u, _, vt = np.linalg.svd(rb[keep].T @ ra[keep])
            fitted = u @ np.diag([1, 1, np.linalg.det(u @ vt)]) @ vt
            residual = np.arccos(np.clip(np.sum(rb * (ra @ fitted.T), axis=1), -1, 1))
            keep = residual < max(3 * np.median(residual[keep]), 1e-4)
        assert keep.sum() > 30, (a, b, keep.sum())
        written = world_from[b].T @ world_from[a]
        fits.append(_rotation_angle(fitted.T @ written))
        assert _rotation_angle(fitted.T @ written @ yaw_rotation(1.0)) > 0.5  # a heading error would show
    db.close()
    assert max(fits) < 0.1, fits
    print("rotation between neighbours, SIFT fit vs written (degrees):", [round(f, 4) for f in fits])


def test_pycolmap_reads_a_model_after_panoproj_is_imported(smooth, tmp_path):
    """In one process with panoproj first: the wheel's static libstdc++ once exported its locale
    facet ids (STB_GNU_UNIQUE, bound process-wide), and pycolmap then failed to parse numbers."""
    import subprocess
    import sys

    path, _ = smooth
    pp.views(path, tmp_path / "out", rig="cube", size=(64, 64))
    code = ("import panoproj, pycolmap, sys; r = pycolmap.Reconstruction(sys.argv[1]); "
            "assert r.num_images() == 6 and r.cameras[1].params[0] == 32, r.summary()")
    p = subprocess.run([sys.executable, "-c", code, str(tmp_path / "out" / "sparse" / "0")], capture_output=True,
                       text=True, timeout=120)
    assert p.returncode == 0, p.stderr[-2000:]
