"""COLMAP models read and written back by panoproj (`panoproj model`, Python's convert_model)
against pycolmap 4.2 (pip, a test-only oracle): a model pycolmap writes (a synthetic
reconstruction with rigs of three cameras, frames, points3D and observations), read and written
by panoproj as text and as binary, read again by pycolmap: every camera, image, rig, frame and
point equal (parameters and poses to 1e-12; they come back bit for bit). COLMAP 3.x models
(no rigs or frames) stay without them. Bad models are refused in one line, nothing written."""
import shutil
import subprocess

import numpy as np
import pytest

import panoproj as pp

# (pycolmap 4.2 has no wheels for Python 3.9: the test extra leaves it out there)
pycolmap = pytest.importorskip("pycolmap")


def synthetic(tmp_path, model_id=pycolmap.CameraModelId.OPENCV_FISHEYE,
              params=(600.0, 601.5, 512.2, 383.7, 0.03, -0.01, 0.002, -0.0003)):
    o = pycolmap.SyntheticDatasetOptions()
    o.num_rigs, o.num_cameras_per_rig, o.num_frames_per_rig, o.num_points3D = 2, 3, 4, 60
    o.camera_model_id, o.camera_params = model_id, list(params)
    db = pycolmap.Database.open(":memory:")
    return pycolmap.synthesize_dataset(o, db)


def write(rec, path, binary):
    path.mkdir(parents=True)
    (rec.write_binary if binary else rec.write_text)(str(path))
    return path


def pose_close(a, b, tol=1e-12):
    return np.abs(a.matrix() - b.matrix()).max() <= tol


def assert_equal(a, b):
    """Every camera, image, rig, frame and point of two pycolmap reconstructions alike."""
    assert sorted(a.cameras) == sorted(b.cameras)
    for i, c in a.cameras.items():
        d = b.cameras[i]
        assert (c.model, c.width, c.height) == (d.model, d.width, d.height)
        assert np.abs(np.array(c.params) - np.array(d.params)).max(initial=0) <= 1e-12
    assert sorted(a.images) == sorted(b.images)
    for i, im in a.images.items():
        jm = b.images[i]
        assert (im.name, im.camera_id, im.frame_id) == (jm.name, jm.camera_id, jm.frame_id)
        assert pose_close(im.cam_from_world(), jm.cam_from_world())
        assert len(im.points2D) == len(jm.points2D)
        for p, q in zip(im.points2D, jm.points2D):
            assert np.abs(p.xy - q.xy).max() <= 1e-12 and p.point3D_id == q.point3D_id
    assert sorted(a.rigs) == sorted(b.rigs)
    for i, r in a.rigs.items():
        s = b.rigs[i]
        assert r.ref_sensor_id == s.ref_sensor_id
        assert sorted(str(k) for k in r.non_ref_sensors) == sorted(str(k) for k in s.non_ref_sensors)
        for k, pose in r.non_ref_sensors.items():
            assert pose_close(pose, s.non_ref_sensors[k])
    assert sorted(a.frames) == sorted(b.frames)
    for i, f in a.frames.items():
        g = b.frames[i]
        assert f.rig_id == g.rig_id and pose_close(f.rig_from_world, g.rig_from_world)
        assert sorted(str(d) for d in f.data_ids) == sorted(str(d) for d in g.data_ids)
    assert sorted(a.points3D) == sorted(b.points3D)
    for i, p in a.points3D.items():
        q = b.points3D[i]
        assert np.abs(p.xyz - q.xyz).max() <= 1e-12 and (p.color == q.color).all() and p.error == q.error
        assert sorted((e.image_id, e.point2D_idx) for e in p.track.elements) == sorted(
            (e.image_id, e.point2D_idx) for e in q.track.elements)


@pytest.mark.parametrize("src_binary", [False, True], ids=["from_txt", "from_bin"])
@pytest.mark.parametrize("out", ["txt", "bin"])
def test_round_trip_through_pycolmap(tmp_path, cli, src_binary, out):
    rec = synthetic(tmp_path)
    src = write(rec, tmp_path / "in", src_binary)
    subprocess.run([cli, "model", str(src), str(tmp_path / "out"), "--format", out, "-q"], check=True)
    back = pycolmap.Reconstruction(str(tmp_path / "out"))
    assert back.num_rigs() == 2 and back.num_frames() == 8 and back.num_images() == 24
    assert_equal(rec, back)
    # Bit for bit: binary -> binary gives COLMAP's own bytes.
    if src_binary and out == "bin":
        for name in ["cameras", "images", "points3D", "rigs", "frames"]:
            assert (src / f"{name}.bin").read_bytes() == (tmp_path / "out" / f"{name}.bin").read_bytes()


def test_every_camera_model_round_trips(tmp_path):
    """A camera of each COLMAP model (its params as pycolmap's defaults) written and read back."""
    rec = pycolmap.Reconstruction()
    names = [m for m in pycolmap.CameraModelId.__members__ if m != "INVALID"]
    for k, name in enumerate(names):
        cam = pycolmap.Camera.create_from_model_name(k + 1, name, 1000.0 + k, 640, 480)
        cam.params = np.array(cam.params) + 1e-3 * np.arange(len(cam.params)) / 7
        rec.add_camera(cam)
    src = write(rec, tmp_path / "in", True)
    pp.convert_model(str(src), str(tmp_path / "out"), format="txt")
    back = pycolmap.Reconstruction(str(tmp_path / "out"))
    assert len(back.cameras) == len(names)
    assert_equal(pycolmap.Reconstruction(str(src)), back)


def test_colmap3_model_without_rigs(tmp_path, cli):
    rec = synthetic(tmp_path, pycolmap.CameraModelId.SIMPLE_RADIAL, [1280.0, 512.0, 384.0, 0.05])
    src = write(rec, tmp_path / "in", False)
    (src / "rigs.txt").unlink()
    (src / "frames.txt").unlink()
    legacy = pycolmap.Reconstruction(str(src))  # (one rig per camera, one frame per image)
    r = subprocess.run([cli, "model", str(src), str(tmp_path / "out"), "--format", "bin"], check=True,
                       capture_output=True, text=True)
    assert "no rigs or frames (COLMAP 3.x)" in r.stdout
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == [
        "cameras.bin", "images.bin", "panoproj-output.json", "points3D.bin"]
    back = pycolmap.Reconstruction(str(tmp_path / "out"))
    for i, im in legacy.images.items():
        assert pose_close(im.cam_from_world(), back.images[i].cam_from_world())
    assert_equal(legacy, back)


def test_a_mistake_fails_the_comparison(tmp_path):
    """The comparison sees a parameter 1e-11 off (the test can fail)."""
    rec = synthetic(tmp_path)
    other = pycolmap.Reconstruction(rec)
    cam = other.cameras[1]
    params = np.array(cam.params)
    params[4] += 1e-11
    cam.params = params
    with pytest.raises(AssertionError):
        assert_equal(rec, other)


def bad(tmp_path, cli, edit, binary=False):
    rec = synthetic(tmp_path)
    src = write(rec, tmp_path / "in", binary)
    edit(src)
    r = subprocess.run([cli, "model", str(src), str(tmp_path / "out")], capture_output=True, text=True)
    assert r.returncode == 1 and not (tmp_path / "out").exists()
    assert len(r.stderr.strip().splitlines()) == 1, r.stderr
    return r.stderr


def replace_line(path, index, new):
    lines = path.read_text().splitlines()
    data = [i for i, line in enumerate(lines) if line and not line.startswith("#")]
    lines[data[index]] = new(lines[data[index]])
    path.write_text("\n".join(lines) + "\n")


CASES = {
    "unknown_model": (lambda d: replace_line(d / "cameras.txt", 0, lambda s: s.replace("OPENCV_FISHEYE", "BOGUS")),
                      "has the model BOGUS"),
    "param_count": (lambda d: replace_line(d / "cameras.txt", 0, lambda s: s + " 0.5"), "has 9 parameters (expected 8)"),
    "camera_unknown": (lambda d: replace_line(d / "images.txt", 0, lambda s: " ".join(s.split()[:8] + ["77"] + s.split()[9:])),
                       "has the camera 77, which cameras does not list"),
    "rig_unknown": (lambda d: replace_line(d / "frames.txt", 0, lambda s: " ".join(s.split()[:1] + ["9"] + s.split()[2:])),
                    "has the rig 9, which rigs does not list"),
    "missing_frames": (lambda d: (d / "frames.txt").unlink(), "has rigs.txt but no frames.txt"),
    "point_unknown": (lambda d: replace_line(d / "points3D.txt", 0, lambda s: " ".join(s.split() + ["999", "0"])),
                      "is seen by the image 999"),
    "nan_pose": (lambda d: replace_line(d / "frames.txt", 0, lambda s: " ".join(s.split()[:2] + ["nan"] + s.split()[3:])),
                 "has the pose nan"),
}


@pytest.mark.parametrize("case", CASES)
def test_bad_text_models_refused(tmp_path, cli, case):
    edit, expected = CASES[case]
    assert expected in bad(tmp_path, cli, edit)


def cut(name, keep):
    def edit(d):
        b = (d / name).read_bytes()
        (d / name).write_bytes(b[:keep(len(b))])
    return edit


def absurd_count(name):
    def edit(d):
        b = bytearray((d / name).read_bytes())
        b[:8] = (10 ** 15).to_bytes(8, "little")
        (d / name).write_bytes(bytes(b))
    return edit


@pytest.mark.parametrize("case, edit, expected", [
    ("images_cut", cut("images.bin", lambda n: n - 5), "points2D at byte"),
    ("points_cut", cut("points3D.bin", lambda n: n // 2), "cut short"),
    ("rigs_cut", cut("rigs.bin", lambda n: n - 1), "cut short"),
    ("frames_absurd", absurd_count("frames.bin"), "says it holds 1000000000000000 frames"),
    ("images_absurd", absurd_count("images.bin"), "says it holds 1000000000000000 images"),
    ("cameras_trailing", lambda d: (d / "cameras.bin").write_bytes((d / "cameras.bin").read_bytes() + b"\0"),
     "1 bytes after its cameras"),
])
def test_bad_binary_models_refused(tmp_path, cli, case, edit, expected):
    assert expected in bad(tmp_path, cli, edit, binary=True)


def test_not_a_model(tmp_path, cli):
    r = subprocess.run([cli, "model", str(tmp_path), str(tmp_path / "out")], capture_output=True, text=True)
    assert r.returncode == 1 and "has no cameras.bin or cameras.txt" in r.stderr
    with pytest.raises(FileNotFoundError):
        pp.convert_model(str(tmp_path / "nothing"), str(tmp_path / "out"))
