"""Video from Python: convert_file (the convert job's typed call) against the command, VideoPlan over
PyAV's frames against the command's lossless output, and the PyAV backend (the plugin made
unloadable) against the plugin: the same frames, times and copied packets. Clips are made here by
FFmpeg's command (lavfi), a few frames each."""
import json
import os
import pickle
import subprocess
import sys
import threading
import warnings

import numpy as np
import pytest

import panoproj as pp
from conftest import child_env

av = pytest.importorskip("av")
ffmpeg = pytest.importorskip("shutil").which("ffmpeg")
pytestmark = pytest.mark.skipif(not ffmpeg, reason="FFmpeg's command makes the clips")



def _clip(path, size="256x128", pix_fmt="yuv420p", codec="libx264", seconds=0.6, audio=True):
    cmd = [ffmpeg, "-v", "error", "-f", "lavfi", "-i", f"testsrc2=s={size}:d={seconds}:r=10"]
    if audio:
        cmd += ["-f", "lavfi", "-i", f"sine=d={seconds}", "-c:a", "aac", "-shortest"]
    subprocess.run(cmd + ["-c:v", codec, "-pix_fmt", pix_fmt, str(path)], check=True)
    return str(path)


@pytest.fixture(scope="module")
def clip(tmp_path_factory):
    return _clip(tmp_path_factory.mktemp("clip") / "in.mp4")


def _frames(path):
    """Every frame's planes (arrays of their widths) and time, as PyAV decodes them."""
    from panoproj import _pyav
    with av.open(path) as c:
        out = []
        for f in c.decode(video=0):
            dtype = np.dtype("<u2") if f.format.components[0].bits > 8 else np.uint8
            out.append(([v.copy() for v in _pyav.plane_views(f, dtype)], float(f.pts * f.time_base)))
        return out


def _packets(path, kind):
    """A stream's packets (time, size, bytes' digest) as ffprobe lists them."""
    r = subprocess.run(["ffprobe", "-v", "error", "-select_streams", kind, "-show_entries", "packet=pts_time,size",
                        "-of", "csv=p=0", path], capture_output=True, text=True, check=True)
    return r.stdout.split()


def _run(script, cwd, pyav_only=True):
    """``script`` in a fresh process (in ``cwd``, this panoproj first on its path), by default one
    whose video plugin cannot load; its stdout's JSON."""
    r = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=cwd,
                       env=child_env(pyav_only))
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout.strip().splitlines()[-1])


def test_convert_file_converts_a_video_as_the_command_does(clip, tmp_path, cli, pond):
    subprocess.run([cli, "convert", clip, str(tmp_path / "cli.mkv"), "--to", "cubemap:layout=eac", "--size", "192x128",
                    "--codec", "ffv1", "-q"], check=True)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = pp.convert_file(clip, tmp_path / "py.mkv", dst=pp.Cubemap(layout="eac"), size=(192, 128), codec="ffv1")
    assert r["frames"] == 6 and r["output_size"] == (192, 128) and r["codec"] == "ffv1"
    ours, theirs = _frames(str(tmp_path / "py.mkv")), _frames(str(tmp_path / "cli.mkv"))
    assert len(ours) == len(theirs) == 6
    for (a, ta), (b, tb) in zip(ours, theirs):
        assert ta == tb and all(np.array_equal(x, y) for x, y in zip(a, b))
    assert _packets(str(tmp_path / "py.mkv"), "a") == _packets(str(tmp_path / "cli.mkv"), "a")
    # The command's warnings are UserWarnings: EAC gets no spherical box.
    assert any(issubclass(w.category, UserWarning) and "no spherical metadata written" in str(w.message)
               for w in caught)
    # start/duration as numbers; an image to an image through the same call.
    r = pp.convert_file(clip, tmp_path / "part.mkv", dst="equirect", codec="ffv1", start=0.2, duration=0.3)
    assert r["frames"] == 3
    pp.convert_file(pond, tmp_path / "pond.jpg", dst="fisheye:fov=180", size=(64, 64))
    assert pp.read(tmp_path / "pond.jpg").shape == (64, 64, 3)


def test_convert_file_refuses_bad_arguments_in_one_line(clip, tmp_path):
    with pytest.raises(TypeError, match="start"):
        pp.convert_file(clip, tmp_path / "x.mkv", dst="equirect", start=[1])
    with pytest.raises(ValueError, match="start"):
        pp.convert_file(clip, tmp_path / "x.mkv", dst="equirect", start=float("nan"))
    with pytest.raises(TypeError, match="dst"):
        pp.convert_file(clip, tmp_path / "x.mkv")  # (dst is required)
    with pytest.raises(ValueError, match="crf"):
        pp.convert_file(clip, tmp_path / "x.mkv", dst="equirect", crf=99)
    (tmp_path / "there.mkv").write_bytes(b"keep")
    with pytest.raises(FileExistsError):
        pp.convert_file(clip, tmp_path / "there.mkv", dst="equirect")
    assert (tmp_path / "there.mkv").read_bytes() == b"keep"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["there.mkv"]


# (nv12: yuv420p frames made semi-planar, as hardware decoders give them)
@pytest.mark.parametrize("pix_fmt,codec,given", [("yuv420p", "libx264", None), ("yuv422p10le", "libx264", None),
                                                 ("yuv420p", "ffv1", "nv12"), ("gbrp10le", "ffv1", None)])
def test_a_video_plan_over_pyav_frames_gives_the_commands_frames(tmp_path, cli, pix_fmt, codec, given):
    src = _clip(tmp_path / "in.mkv", size="320x160", pix_fmt=pix_fmt, codec=codec, audio=False)
    subprocess.run([cli, "convert", src, str(tmp_path / "cli.mkv"), "--to", "cubemap:layout=3x2", "--size", "240x160",
                    "--codec", "ffv1", "-q"], check=True, capture_output=True)
    with av.open(src) as c:
        stream = c.streams.video[0]
        frames = [f.reformat(format=given) if given else f for f in c.decode(stream)]
        plan = pp.VideoPlan("equirect", "cubemap:layout=3x2", frames[0] if given else stream, size=(240, 160))
        assert plan.size == (240, 160) and plan.pixel_format == pix_fmt
        ours = [plan(f) for f in frames]
    theirs = _frames(str(tmp_path / "cli.mkv"))
    assert len(ours) == len(theirs) == 6
    from panoproj import _pyav
    for o, (planes, t) in zip(ours, theirs):
        assert float(o.pts * o.time_base) == pytest.approx(t, abs=1e-3)
        views = _pyav.plane_views(o, planes[0].dtype)
        assert all(np.array_equal(v, p) for v, p in zip(views, planes)), pix_fmt


def test_a_video_plan_reads_and_writes_in_place_pickles_and_runs_on_threads(tmp_path):
    src = _clip(tmp_path / "in.mkv", size="512x256", codec="ffv1", audio=False)
    with av.open(src) as c:
        frames = list(c.decode(video=0))
    plan = pp.VideoPlan("equirect", "fisheye:fov=180", frames[0], size=(256, 256))
    from panoproj import _pyav
    planes = _pyav.plane_views(frames[0], np.uint8)
    assert all(p.flags.c_contiguous for p in planes)  # (512 and 256 wide: rows back to back)
    out = av.VideoFrame(256, 256, "yuv420p")
    before = [v.__array_interface__["data"][0] for v in _pyav.plane_views(out, np.uint8)]
    assert plan.run(frames[0], out=out) is out
    assert [v.__array_interface__["data"][0] for v in _pyav.plane_views(out, np.uint8)] == before
    expected = [plan.run_planes(_pyav.plane_views(f, np.uint8)) for f in frames]
    again = pickle.loads(pickle.dumps(plan))
    assert all(np.array_equal(a, b) for a, b in zip(again.run_planes(_pyav.plane_views(frames[1], np.uint8)),
                                                    expected[1]))
    results = [None] * len(frames)

    def one(i):
        results[i] = plan.run_planes(_pyav.plane_views(frames[i], np.uint8))

    threads = [threading.Thread(target=one, args=(i,)) for i in range(len(frames))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for got, want in zip(results, expected):
        assert all(np.array_equal(a, b) for a, b in zip(got, want))
    # Outside the fisheye's circle: video black (Y 16, chroma 128 for limited range).
    y, cb, _ = expected[0]
    assert y[0, 0] == 16 and cb[0, 0] == 128


def test_a_video_plan_refuses_what_it_cannot_convert(tmp_path):
    frame = av.VideoFrame(256, 128, "yuv420p")
    with pytest.raises(TypeError, match="like"):
        pp.VideoPlan("equirect", "cubemap", np.zeros((128, 256), np.uint8))
    with pytest.raises(ValueError, match="chroma_siting"):
        pp.VideoPlan("equirect", "cubemap", frame, size=(384, 64), chroma_siting="middle")
    with pytest.raises(ValueError, match="does not hold whole chroma samples.*give size=246x164"):
        pp.VideoPlan("equirect", "cubemap:layout=3x2", frame, size=(243, 162))
    with pytest.warns(UserWarning, match="made 246x164"):
        pp.VideoPlan("equirect", "cubemap:layout=3x2", frame)  # (the default, 243x162, made whole)
    with pytest.raises(ValueError, match="engine"):
        pp.VideoPlan("equirect", "cubemap", frame, size=(384, 64), engine="reference")
    with pytest.raises(ValueError, match="pixel format pal8"):
        pp.VideoPlan("equirect", "cubemap", av.VideoFrame(256, 128, "pal8"))
    plan = pp.VideoPlan("equirect", "cubemap", frame, size=(384, 64))
    with pytest.raises(ValueError, match="the plan is for 256x128 yuv420p"):
        plan(av.VideoFrame(128, 64, "yuv420p"))
    with pytest.raises(ValueError, match="the plan is for 256x128 yuv420p"):
        plan(av.VideoFrame(256, 128, "yuv444p"))
    with pytest.raises(TypeError, match="av.VideoFrame"):
        plan(np.zeros((128, 256), np.uint8))
    with pytest.raises(TypeError, match="uint8"):
        plan.run_planes([np.zeros((128, 256), np.uint16)] + [np.zeros((64, 128), np.uint16)] * 2)
    with pytest.raises(ValueError, match="input plane 1"):
        plan.run_planes([np.zeros((128, 256), np.uint8)] * 3)
    with pytest.raises(ValueError, match="planes: 2 in"):
        plan.run_planes([np.zeros((128, 256), np.uint8)] * 2)
    ro = [np.zeros(s[::-1], np.uint8) for s in plan.plane_sizes()]
    ro[0].flags.writeable = False
    with pytest.raises(ValueError, match="writable"):
        plan.run_planes([np.zeros((128, 256), np.uint8)] + [np.zeros((64, 128), np.uint8)] * 2, out=ro)


def test_through_pyav_a_video_converts_to_the_plugins_frames_and_packets(clip, tmp_path):
    # The plugin's outputs first, here; then the same calls where it cannot load.
    calls = [("{clip}", "v.mkv", dict(dst="cubemap:layout=3x2", size=(240, 160), codec="ffv1")),
             ("{clip}", "part.mkv", dict(dst="equirect", codec="ffv1", start=0.2, duration=0.3)),
             ("{clip}", "f/{n}.png", dict(dst="fisheye:fov=180", size=(96, 96))),
             ("@f", "again.mkv", dict(src="fisheye:fov=180", dst="equirect", size=(128, 64), codec="ffv1", fps=10))]
    script = f"""
import json, os, sys, warnings, panoproj as pp
os.makedirs("f", exist_ok=True)
warnings.simplefilter("always")
out = {{}}
with warnings.catch_warnings(record=True) as caught:
    for src, dst, kw in {calls!r}:
        src = sorted("f/" + n for n in os.listdir("f")) if src == "@f" else src.format(clip={clip!r})
        out[dst] = pp.convert_file(src, dst, **kw)["frames"]
out["warnings"] = [str(w.message) for w in caught]
out["version"] = pp._pyav.version()
print(json.dumps(out))
"""
    (tmp_path / "plugin").mkdir()
    (tmp_path / "pyav").mkdir()
    _run(script, tmp_path / "plugin", pyav_only=False)
    got = _run(script, tmp_path / "pyav")
    assert got["v.mkv"] == 6 and got["part.mkv"] == 3 and got["f/{n}.png"] == 6 and got["again.mkv"] == 6
    for name in ("v.mkv", "part.mkv", "again.mkv"):
        ours, theirs = _frames(str(tmp_path / "pyav" / name)), _frames(str(tmp_path / "plugin" / name))
        assert len(ours) == len(theirs)
        for (a, ta), (b, tb) in zip(ours, theirs):
            assert ta == tb and all(np.array_equal(x, y) for x, y in zip(a, b)), name
    assert _packets(str(tmp_path / "pyav" / "v.mkv"), "a") == _packets(str(tmp_path / "plugin" / "v.mkv"), "a")
    for n in range(6):
        assert np.array_equal(pp.read(tmp_path / "pyav" / "f" / f"{n}.png"),
                              pp.read(tmp_path / "plugin" / "f" / f"{n}.png"))
    # What PyAV does not carry is said: no spherical metadata written into Matroska.
    said = " ".join(got["warnings"])
    assert "part.mkv: no spherical metadata written: through PyAV panoproj writes it into MP4 only" in said
    assert got["version"].startswith("PyAV ")


def _side_data(path):
    r = subprocess.run(["ffprobe", "-v", "error", "-select_streams", "v", "-show_entries", "stream_side_data",
                        "-of", "default=nw=1", path], capture_output=True, text=True, check=True)
    return r.stdout


def test_through_pyav_an_mp4s_spherical_metadata_is_read_and_written_as_the_plugin_does(clip, tmp_path):
    made = {"crop.mp4": dict(dst="equirect:hfov=180,vfov=90,lon0=45", size=(128, 64)),
            "cube.mp4": dict(dst="cubemap:layout=3x2,order=rludfb", size=(192, 128)),
            "tb.mp4": dict(dst="equirect:stereo=tb", size=(256, 256)),
            "e.mkv": dict(dst="equirect", size=(256, 128), codec="ffv1")}
    (tmp_path / "plugin").mkdir()
    for name, kw in made.items():
        pp.convert_file(clip, tmp_path / "plugin" / name, **kw)
    # A pose in the cube's prhd box (yaw 90): read, it turns the frames.
    cube = bytearray((tmp_path / "plugin" / "cube.mp4").read_bytes())
    k = cube.find(b"prhd") + 8
    cube[k:k + 4] = (90 << 16).to_bytes(4, "big")
    (tmp_path / "plugin" / "posed.mp4").write_bytes(bytes(cube))
    back = dict(dst="equirect", size=(256, 128), codec="ffv1")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for src, out in (("posed.mp4", "from_posed.mkv"), ("e.mkv", "from_e.mkv")):
            pp.convert_file(tmp_path / "plugin" / src, tmp_path / "plugin" / out, **back)
    plugin = str(tmp_path / "plugin")
    script = f"""
import json, warnings, panoproj as pp
out = {{}}
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    for name, kw in {made!r}.items():
        out[name] = pp.convert_file({clip!r}, name, **kw)["spherical_metadata"]
    for src, name in (("posed.mp4", "from_posed.mkv"), ("e.mkv", "from_e.mkv")):
        out[name] = pp.convert_file({plugin!r} + "/" + src, name, **{back!r})["src"]
out["warnings"] = [str(w.message) for w in caught]
print(json.dumps(out))
"""
    got = _run(script, tmp_path)
    for name in ("crop.mp4", "cube.mp4", "tb.mp4"):
        assert "Spherical Mapping" in _side_data(str(tmp_path / name))
        assert _side_data(str(tmp_path / name)) == _side_data(str(tmp_path / "plugin" / name)), name
    assert "(its spherical metadata: cubemap, pose yaw 90 pitch 0 roll 0)" in got["from_posed.mkv"], got
    # The report says what was written.
    assert got["cube.mp4"] == "cubemap" and got["tb.mp4"] == "equirectangular, stereo top-bottom", got
    assert got["crop.mp4"].startswith("equirectangular, bounds left 0.375") and got["e.mkv"] == "", got
    for name in ("from_posed.mkv", "from_e.mkv"):
        ours, theirs = _frames(str(tmp_path / name)), _frames(str(tmp_path / "plugin" / name))
        assert len(ours) == len(theirs) == 6
        for (a, _), (b, _) in zip(ours, theirs):
            assert all(np.array_equal(x, y) for x, y in zip(a, b)), name
    assert got["from_e.mkv"] == "equirect (its spherical metadata: equirectangular)", got  # (Matroska's, read)
    said = " ".join(got["warnings"])
    assert "e.mkv: no spherical metadata written: through PyAV panoproj writes it into MP4 only" in said


def test_through_pyav_bad_inputs_fail_in_one_line_and_leave_nothing(clip, tmp_path):
    (tmp_path / "junk.mp4").write_bytes(b"\x00\x00\x00\x18ftypisom" + os.urandom(2000))
    script = f"""
import json, os, panoproj as pp
out = {{}}
def attempt(name, *a, **kw):
    try:
        pp.convert_file(*a, **kw)
        out[name] = "no error"
    except Exception as e:
        out[name] = [type(e).__name__, str(e)]
attempt("junk", "junk.mp4", "a.mkv", dst="equirect")
attempt("stream", {clip!r}, "b.mkv", dst="equirect", stream=3)
attempt("preset", {clip!r}, "c.mp4", dst="equirect", preset="warp9")
attempt("late", {clip!r}, "d.mkv", dst="equirect", start=30)
out["left"] = sorted(os.listdir("."))
print(json.dumps(out))
"""
    got = _run(script, tmp_path)
    assert got["junk"][0] == "OSError" and "cannot read junk.mp4: it is not a video PyAV can read" in got["junk"][1]
    assert got["stream"][0] == "OSError" and "--stream 3 is out of range: it has 1 video stream" in got["stream"][1]
    assert got["preset"][0] == "OSError" and "encoder libx264 refuses these settings" in got["preset"][1]
    assert got["late"][0] == "OSError" and "it has no frame from 30" in got["late"][1]
    assert all("\n" not in v[1] for k, v in got.items() if k != "left")
    assert got["left"] == ["junk.mp4"]  # (no output, no temporary)


def test_without_plugin_or_pyav_video_fails_naming_both(clip, tmp_path):
    script = f"""
import json, sys
sys.modules["av"] = None  # (PyAV hidden: its import fails)
import panoproj as pp
try:
    pp.convert_file({clip!r}, "x.mkv", dst="equirect")
    print(json.dumps("no error"))
except OSError as e:
    print(json.dumps(str(e)))
"""
    said = _run(script, tmp_path)
    assert "FFmpeg's libraries (apt install libavformat59" in said and "PyAV (pip install 'panoproj[av]')" in said
    assert "\n" not in said and not (tmp_path / "x.mkv").exists()


# VLC's renderer of Spherical Video V2's cbmp layout 0 ("cubemap standard", its OpenGL output's
# cube): each face's corners in VLC's space (x right, y up, front at z = -1) and the grid point
# (column of 3, row of 2, from the top left) its texture takes there. Facts of VLC's
# modules/video_output/opengl/vout_helper.c (BuildCube), which plays YouTube's cubemap videos.
VLC_LAYOUT_0 = {
    "front": [((-1, 1, -1), (1, 1)), ((-1, -1, -1), (1, 2)), ((1, 1, -1), (2, 1)), ((1, -1, -1), (2, 2))],
    "back": [((-1, 1, 1), (3, 1)), ((-1, -1, 1), (3, 2)), ((1, 1, 1), (2, 1)), ((1, -1, 1), (2, 2))],
    "left": [((-1, 1, -1), (2, 0)), ((-1, -1, -1), (2, 1)), ((-1, 1, 1), (1, 0)), ((-1, -1, 1), (1, 1))],
    "right": [((1, 1, -1), (0, 0)), ((1, -1, -1), (0, 1)), ((1, 1, 1), (1, 0)), ((1, -1, 1), (1, 1))],
    "bottom": [((-1, -1, 1), (0, 2)), ((-1, -1, -1), (0, 1)), ((1, -1, 1), (1, 2)), ((1, -1, -1), (1, 1))],
    "top": [((-1, 1, 1), (2, 0)), ((-1, 1, -1), (2, 1)), ((1, 1, 1), (3, 0)), ((1, 1, -1), (3, 1))],
}


def test_the_cube_cbmp_layout_0_names_is_the_one_vlc_plays():
    # The spec panoproj reads layout 0 as, and writes layout 0 for (jobs/video_spherical.hpp).
    spec, cell = "cubemap:layout=3x2,order=rludfb", 100
    for face, corners in VLC_LAYOUT_0.items():
        centre = np.mean([g for _, g in corners], axis=0) * cell
        for (x, y, z), grid in corners:
            px = np.array(grid, float) * cell
            px += np.sign(centre - px) * 0.5  # (the corner pixel's centre, inside the face)
            ray, ok = pp.to_ray(spec, (3 * cell, 2 * cell), px[:1], px[1:])
            want = np.array([x, -y, -z], float) / np.sqrt(3)  # (in panoproj's axes: y down, z forward)
            assert ok[0] and np.allclose(ray[0], want, atol=0.01), (face, grid, ray[0], want)
