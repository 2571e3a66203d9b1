"""Projections from keywords and spec text, every dtype and layout, rays and pixels, files with
metadata, plans and pickling."""
import pickle

import numpy as np
import pytest

import panoproj as pp
from conftest import smooth_equirect

ALL = ["pinhole:hfov=100", "fisheye:fov=250,model=equisolid", "fisheye:fov=180,model=orthographic",
       "equirect:hfov=200,vfov=120,lon0=30", "cylindrical", "cubemap", "cubemap:layout=cross", "aitoff",
       "hammer", "eckert-greifendorff", "bonne:phi1=30", "dual-fisheye:fov=180,roll2=90"]


def test_every_catalogue_projection_is_exported():
    names = [d["name"] for d in pp._core.catalog()]
    exported = {c.name for c in (getattr(pp, n) for n in pp.__all__) if isinstance(c, type) and issubclass(c, pp.Projection) and c is not pp.Projection}
    assert exported == set(names)
    assert pp.DualFisheye().name == "dual-fisheye"


def test_every_table_option_is_a_keyword_where_the_table_says():
    import inspect
    rows = pp._core.options()
    for fn, use in ((pp.convert, "convert"), (pp.build_map, "maps"), (pp.Plan.__init__, "convert")):
        params = inspect.signature(fn).parameters
        for o in rows:
            assert (o["name"] in params) == (use in o["use"]), (fn, o["name"])
            if use in o["use"]:
                assert params[o["name"]].kind is inspect.Parameter.KEYWORD_ONLY
                assert o["help"] in fn.__doc__
    with pytest.raises(TypeError, match="unknown option 'zoom'"):
        pp.convert(np.zeros((8, 16, 3), np.uint8), "equirect", "pinhole", zoom=2)
    with pytest.raises(TypeError, match="unknown option 'interp'"):
        pp.build_map("equirect", "pinhole", (16, 8), interp="bicubic")


def test_keyword_constructors_and_spec_text_agree():
    f = pp.Fisheye(fov=180, model="equisolid")
    assert str(f) == "fisheye:fov=180,model=equisolid"
    assert repr(f) == "Fisheye(fov=180, model='equisolid')"
    assert pp.projection("fisheye:model=equisolid,fov=180") == f
    assert isinstance(pp.projection("eckert-greifendorff"), pp.EckertGreifendorff)
    assert repr(pp.Pinhole(hfov=97.5)) == "Pinhole(hfov=97.5)"
    assert pickle.loads(pickle.dumps(f)) == f
    for spec in ALL:
        p = pp.projection(spec)
        assert eval(repr(p), vars(pp)) == p  # the repr is the constructor call
    assert "fov" in pp.Fisheye.__doc__


@pytest.mark.parametrize("spec", ALL)
def test_to_pixel_inverts_to_ray_on_every_projection(spec):
    size = (600, 100) if "cubemap" in spec and "cross" not in spec else (400, 300) if "cross" in spec else (320, 200)
    rng = np.random.default_rng(1)
    x = rng.uniform(0, size[0], 5000)
    y = rng.uniform(0, size[1], 5000)
    rays, ok = pp.to_ray(spec, size, x, y)
    assert ok.sum() > 1000
    assert np.allclose(np.linalg.norm(rays[ok], axis=-1), 1, atol=1e-12)
    x2, y2, ok2 = pp.to_pixel(spec, size, rays[ok])
    assert ok2.all()
    assert np.abs(x2 - x[ok]).max() < 1e-6 and np.abs(y2 - y[ok]).max() < 1e-6
    # Shapes are kept: a 2-D grid of positions gives a 2-D grid of rays.
    r2, ok3 = pp.to_ray(spec, size, x[:20].reshape(4, 5), y[:20].reshape(4, 5))
    assert r2.shape == (4, 5, 3) and ok3.shape == (4, 5)


@pytest.mark.parametrize("dtype,bound", [(np.uint8, 1), (np.uint16, 1), (np.float16, 4.9e-4), (np.float32, 2e-3)])
@pytest.mark.parametrize("channels", [1, 2, 3, 4])
def test_every_dtype_and_channel_count_against_the_exact_engine(dtype, channels, bound):
    img = smooth_equirect(256, 128, dtype, channels)
    if channels == 1:
        img = img[..., 0].copy()  # HxW in, HxW out
    # (the reference engine has no antialiasing: compare without)
    fast = pp.convert(img, "equirect", "fisheye:fov=190", size=(96, 96), yaw=20, interp="bicubic",
                      antialias="off")
    exact = pp.convert(img, "equirect", "fisheye:fov=190", size=(96, 96), yaw=20, interp="bicubic",
                       engine="reference")
    assert fast.dtype == img.dtype and fast.shape == exact.shape
    assert fast.shape == ((96, 96) if channels == 1 else (96, 96, channels))
    assert np.abs(fast.astype(np.float64) - exact.astype(np.float64)).max() <= bound
    assert fast.astype(np.float64).max() > 0.3 * (np.iinfo(dtype).max if np.issubdtype(dtype, np.integer) else 1)


def test_round_trip_through_a_cube_of_faces():
    img = smooth_equirect(512, 256)
    # Without antialiasing: near its corners the cube shrinks the source, and what antialiasing
    # removes there the way back cannot restore.
    cube = pp.convert(img, "equirect", "cubemap", size=(6 * 160, 160), interp="bicubic", antialias="off")
    faces = pp.split_faces(cube)
    assert len(faces) == 6 and all(f.shape == (160, 160, 3) for f in faces)
    assert all(np.shares_memory(f, cube) for f in faces)
    back = pp.convert(faces, "cubemap", "equirect", size=(512, 256), interp="bicubic")
    assert np.array_equal(back, pp.convert(cube, "cubemap", "equirect", size=(512, 256), interp="bicubic"))
    err = np.abs(back.astype(int) - img.astype(int))
    assert np.percentile(err, 99) <= 2


def test_plan_equals_convert_and_survives_pickling():
    img = smooth_equirect(512, 256)
    kw = dict(size=(200, 150), yaw=10, pitch=5, roll=2, interp="lanczos3")
    plan = pp.Plan(pp.Equirect(), pp.Pinhole(hfov=80), (512, 256), **kw)
    assert plan.size == (200, 150) and plan.src == pp.Equirect() and plan.source_size == (512, 256)
    expected = pp.convert(img, "equirect", "pinhole:hfov=80", **kw)
    assert np.array_equal(plan(img), expected)
    assert np.array_equal(plan(img), expected)  # second run: the kept map
    clone = pickle.loads(pickle.dumps(plan))
    assert repr(clone) == repr(plan)
    assert np.array_equal(clone(img), expected)


def test_plan_runs_after_the_first_equal_convert_on_every_frame_and_layout():
    # uint8 bilinear: the first run keeps its planned taps, later runs of that layout replay them.
    frames = [smooth_equirect(512, 256), np.ascontiguousarray(smooth_equirect(512, 256)[:, ::-1])]
    frames += [frames[0][..., 0], np.dstack([frames[1], frames[0][..., :1]]), frames[1], frames[0]]
    for dst, kw in [("cubemap:layout=cross", dict(size=(384, 288), interp="bilinear", antialias="off")),
                    ("pinhole:hfov=150", dict(size=(256, 192), interp="bilinear", pitch=60))]:
        plan = pp.Plan("equirect", dst, (512, 256), **kw)
        for img in frames:  # RGB, RGB, gray, RGBX without alpha, then RGB again
            assert np.array_equal(plan(img), pp.convert(img, "equirect", dst, **kw))


def test_build_map_panoproj_convention_is_the_opencv_one_shifted():
    mx, my = pp.build_map("equirect", "pinhole", (512, 256), size=(64, 48))
    px, py = pp.build_map("equirect", "pinhole", (512, 256), size=(64, 48), convention="panoproj")
    assert np.allclose(px - 0.5, mx) and np.allclose(py - 0.5, my)
    fx, _ = pp.build_map("equirect", "fisheye", (512, 256), size=(64, 64), convention="panoproj")
    assert np.isnan(fx[0, 0]) and not np.isnan(fx[32, 32])  # the corner is outside the circle


@pytest.mark.parametrize("ext,dtype", [("png", np.uint16), ("tif", np.uint8), ("exr", np.float16),
                                       ("exr", np.float32), ("jpg", np.uint8)])
def test_write_read_round_trip_with_metadata(tmp_path, ext, dtype):
    img = smooth_equirect(64, 32, dtype)
    path = str(tmp_path / f"x.{ext}")
    pp.write(path, img, metadata={"ImageDescription": "panoproj test", "Artist": "someone"})
    back, md = pp.read(path, metadata=True)
    assert back.dtype == img.dtype and back.shape == img.shape
    if ext != "jpg":
        assert np.array_equal(back, img)
    assert md.get("ImageDescription") == "panoproj test" and md.get("Artist") == "someone"
    pp.write(path, img[:, :, :1].copy(), overwrite=True)
    assert pp.read(path).shape == (32, 64)


def test_write_converts_samples_and_cube_faces_as_files(tmp_path):
    img = smooth_equirect(64, 32, np.float32)
    pp.write(str(tmp_path / "a.png"), img, dtype="uint8")
    assert pp.read(str(tmp_path / "a.png")).dtype == np.uint8
    cube = pp.convert(smooth_equirect(256, 128), "equirect", "cubemap", size=(6 * 32, 32))
    pp.write(str(tmp_path / "{face}.png"), cube)
    assert np.array_equal(pp.read(str(tmp_path / "{face}.png")), cube)
    assert np.array_equal(pp.read(str(tmp_path / "up.png")), pp.split_faces(cube)[4])


def test_antialias_choices():
    # A 4x shrink: auto and 3x3 sub-pixels differ from off, and Plan gives convert's bytes.
    img = smooth_equirect(1024, 512)
    args = ("equirect", "fisheye:fov=180")
    off = pp.convert(img, *args, size=(128, 128), interp="bilinear", antialias="off")
    auto = pp.convert(img, *args, size=(128, 128), interp="bilinear")
    assert np.array_equal(auto, pp.convert(img, *args, size=(128, 128), interp="bilinear", antialias="auto"))
    sub = pp.convert(img, *args, size=(128, 128), interp="bilinear", antialias=3)
    assert not np.array_equal(auto, off) and not np.array_equal(sub, off)
    plan = pp.Plan(*args, (1024, 512), size=(128, 128), interp="bilinear", antialias="3")
    assert np.array_equal(plan(img), sub)
    assert "antialias='3'" in repr(plan)
    assert np.array_equal(pickle.loads(pickle.dumps(plan))(img), sub)
    # The reference engine has none: its default is off, and asking for it is an error.
    ref = pp.convert(img, *args, size=(128, 128), interp="bilinear", engine="reference")
    assert np.abs(ref.astype(int) - off.astype(int)).max() <= 1
    with pytest.raises(ValueError, match="needs the simd or scalar engine"):
        pp.convert(img, *args, size=(128, 128), engine="reference", antialias="auto")
    with pytest.raises(ValueError, match="antialias '1'"):
        pp.convert(img, *args, antialias="1")
    with pytest.raises(TypeError, match="antialias"):
        pp.convert(img, *args, antialias=True)


def test_dual_fisheye_both_ways_blended_and_cut():
    """A 360 camera's two lenses side by side: equirect -> dual fisheye -> equirect comes back; the
    feathered blend differs from the hard cut only in the overlap, and a feather wider than the
    overlap is a ValueError naming it."""
    img = smooth_equirect(512, 256)
    lenses = pp.DualFisheye(fov=200)
    assert str(lenses) == "dual-fisheye:fov=200"
    kw = dict(size=(512, 256), interp="bicubic", antialias="off")
    dual = pp.convert(img, "equirect", lenses, **kw)
    back = pp.convert(dual, lenses, "equirect", **kw)
    cut = pp.convert(dual, pp.DualFisheye(fov=200, feather=0), "equirect", **kw)
    err = np.abs(back.astype(int) - img).max(axis=-1)
    assert np.percentile(err, 99) <= 3
    # Longitudes within 80..100 degrees of lens 0's axis (+z) see both lenses: only there may the
    # blend and the cut differ.
    lon = np.degrees(np.abs((np.arange(512) + 0.5) / 512 * 2 * np.pi - np.pi))
    lat = np.degrees(np.pi / 2 - (np.arange(256) + 0.5) / 256 * np.pi)
    off_axis = np.degrees(np.arccos(np.cos(np.radians(lat))[:, None] * np.cos(np.radians(lon))[None, :]))
    differ = np.abs(cut.astype(int) - back).max(axis=-1) > 0
    assert differ.any() and (np.abs(off_axis[differ] - 90) <= 10.5).all()
    with pytest.raises(ValueError, match="wider than the lenses' overlap of 20"):
        pp.convert(dual, pp.DualFisheye(fov=200, feather=30), "equirect", **kw)


def test_alpha_and_fill_at_the_fields_edge():
    """alpha=True adds an alpha channel, 0 outside a fisheye's circle and antialiased on its rim;
    fill colours the outside and equals the alpha output over that colour; a Plan does the same
    and pickles its edge options."""
    img = smooth_equirect(256, 128)
    kw = dict(size=(61, 61), interp="bilinear")
    a = pp.convert(img, "equirect", "fisheye:fov=180", alpha=True, **kw)
    assert a.shape == (61, 61, 4)
    assert a[0, 0, 3] == 0 and a[30, 30, 3] == 255
    assert ((a[..., 3] > 0) & (a[..., 3] < 255)).sum() > 50
    f = pp.convert(img, "equirect", "fisheye:fov=180", fill=(0.25, 0.5, 0.75), **kw)
    assert f.shape == (61, 61, 3) and tuple(f[0, 0]) == (64, 128, 191)
    w = a[..., 3:] / 255.0
    over = w * a[..., :3] + (1 - w) * np.array([64, 128, 191.25])
    assert np.abs(over - f).max() <= 1.5
    hexed = pp.convert(img, "equirect", "fisheye:fov=180", fill="#4080bf", **kw)  # 191 / 255 against 0.75
    assert np.abs(hexed.astype(int) - f).max() <= 1
    plan = pp.Plan("equirect", "fisheye:fov=180", (256, 128), alpha=True, **kw)
    assert np.array_equal(plan(img), a)
    assert np.array_equal(pickle.loads(pickle.dumps(plan))(img), a)
    with pytest.raises(ValueError, match="fill colour 'red'"):
        pp.convert(img, "equirect", "fisheye:fov=180", fill="red", **kw)
    with pytest.raises(TypeError, match="fill"):
        pp.convert(img, "equirect", "fisheye:fov=180", fill=object(), **kw)


def test_the_module_loads_openimageio_only_for_files_that_need_it(tmp_path):
    # Run in a fresh interpreter: this one may have loaded the plugin already.
    code = f"""
import numpy as np, panoproj as pp
maps = lambda: open('/proc/self/maps').read()
assert 'OpenImageIO' not in maps(), 'import'
a = (np.arange(64 * 32 * 3) % 251).astype(np.uint8).reshape(32, 64, 3)
for ext in ('jpg', 'png', 'ppm'):
    pp.write(r'{tmp_path}/a.' + ext, a)
    pp.convert(pp.read(r'{tmp_path}/a.' + ext), 'equirect', 'cubemap', size=(48, 8))
assert 'OpenImageIO' not in maps(), 'jpeg, png, ppm'
pp.write(r'{tmp_path}/a.tif', a)
assert 'OpenImageIO' in maps(), 'tiff'
"""
    import subprocess
    import sys
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_jpeg_quality_and_subsampling(tmp_path):
    a = np.random.default_rng(1).integers(0, 255, (64, 96, 3), dtype=np.uint8)
    sizes = []
    for q in (20, 60, 95):
        pp.write(str(tmp_path / f"q{q}.jpg"), a, quality=q)
        sizes.append((tmp_path / f"q{q}.jpg").stat().st_size)
    assert sizes == sorted(sizes)
    pp.write(str(tmp_path / "s.jpg"), a, subsampling="444")
    b = (tmp_path / "s.jpg").read_bytes()
    sof = b.find(b"\xff\xc0")
    assert b[sof + 11] == 0x11  # luma sampled 1x1: no chroma subsampling
    with pytest.raises(ValueError, match="quality: 0"):
        pp.write(str(tmp_path / "bad.jpg"), a, quality=0)
    with pytest.raises(ValueError, match="subsampling 411"):
        pp.write(str(tmp_path / "bad.jpg"), a, subsampling="411")
    assert not (tmp_path / "bad.jpg").exists()


def test_write_and_the_folder_jobs_take_their_defaults_from_the_rows():
    # write's options are the write rows (the command's --overwrite, --quality, --subsampling);
    # tiles' and views' arguments are their jobs' rows (generated: python/generate_api.py).
    import ast
    import inspect
    rows = {r["name"]: r for r in pp._core.write_options()}
    write = inspect.signature(pp.write).parameters
    for name in ("overwrite", "quality", "subsampling"):
        assert write[name].default == ast.literal_eval(rows[name]["default"]), name
    for job in pp._core.jobs():
        if not job["python"]:
            continue
        params = inspect.signature(getattr(pp, job["python_name"])).parameters
        for r in job["rows"]:
            if r["python"] and r["required"] and not r["positional"]:
                assert params[r["name"]].default is inspect.Parameter.empty, (job["name"], r["name"])
            elif r["python"] and not r["positional"]:
                assert params[r["name"]].default == ast.literal_eval(r["default"]), (job["name"], r["name"])
