"""Rigs of lenses (stitch rig.yaml pano.jpg): a rig of the two lenses of a dual-fisheye frame gives
the dual-fisheye conversion within 1 LSB; 3- and 4-lens rigs rendered from an analytic scene
rebuild it at least as well as the dual-fisheye path; a template rig takes other frames."""
import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import panoproj as pp

ROOT = Path(__file__).resolve().parents[2]
CLI = os.environ.get("PANOPROJ_CLI", str(ROOT / "build/tools/panoproj"))
JORDAN = ROOT / "samples/images/jordan_pond_4096x2048.jpg"


def rotation(yaw, pitch, roll):
    """rotation.hpp's R = Ry(yaw) Rx(pitch) Rz(roll): a lens's rays into the rig's."""
    y, p, r = np.radians([yaw, pitch, roll])
    ry = np.array([[np.cos(y), 0, np.sin(y)], [0, 1, 0], [-np.sin(y), 0, np.cos(y)]])
    rx = np.array([[1, 0, 0], [0, np.cos(p), -np.sin(p)], [0, np.sin(p), np.cos(p)]])
    rz = np.array([[np.cos(r), -np.sin(r), 0], [np.sin(r), np.cos(r), 0], [0, 0, 1]])
    return ry @ rx @ rz


def scene(rays):
    """A colour field smooth everywhere on the sphere, poles too (the truth), in 0.1..0.9."""
    x, y, z = rays[..., 0], rays[..., 1], rays[..., 2]
    return np.stack([0.5 + 0.4 * np.sin(14 * x + 9 * y),
                     0.5 + 0.4 * np.sin(11 * z - 8 * y + 1),
                     0.5 + 0.4 * np.cos(9 * x * z + 6 * y)], -1).astype(np.float32)


def render(spec, size, yaw=0.0, pitch=0.0, roll=0.0):
    """The scene through a lens (spec at size WxH) at its pose; alpha 0 where it has no ray."""
    w, h = size
    xs, ys = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    rays, ok = pp.to_ray(spec, size, xs, ys)
    rays = np.nan_to_num(rays) @ rotation(yaw, pitch, roll).T
    out = np.zeros((h, w, 4), np.float32)
    out[..., :3] = scene(rays)
    out[..., 3] = ok
    out[~ok] = 0
    return out


def truth(size):
    w, h = size
    xs, ys = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    return scene(pp.to_ray("equirect", size, xs, ys)[0])


def psnr(a, b):
    return 10 * np.log10(1 / np.mean((a.astype(np.float64) - b) ** 2))


def write_rig(path: Path, lenses):
    path.write_text("lenses:\n" + "".join(
        "  - {" + ", ".join(f"{k}: '{v}'" if k == "spec" else f"{k}: {v}" for k, v in lens.items()) + "}\n"
        for lens in lenses))
    return path


@pytest.mark.parametrize("layout", ["side-by-side", "top-bottom"])
def test_a_dual_fisheye_rig_is_the_dual_fisheye_conversion(tmp_path, layout):
    src = pp.read(str(JORDAN))[::2, ::2]
    size = (2048, 1024) if layout == "side-by-side" else (1024, 2048)
    frame = pp.convert(src, "equirect", f"dual-fisheye:fov=200,layout={layout}", size=size, interp="bicubic")
    pp.write(str(tmp_path / "frame.png"), frame)
    half = "1024x1024+1024+0" if layout == "side-by-side" else "1024x1024+0+1024"
    lenses = [{"name": "front", "spec": "fisheye:fov=200", "input": "frame.png", "rect": "1024x1024+0+0"},
              {"name": "back", "spec": "fisheye:fov=200", "input": "frame.png", "rect": half, "yaw": 180}]
    # JSON for one layout, YAML for the other: the same rig.
    if layout == "top-bottom":
        rig = tmp_path / "rig.json"
        rig.write_text(json.dumps({"lenses": lenses}))
    else:
        rig = write_rig(tmp_path / "rig.yaml", lenses)
    expected = pp.convert(frame, f"dual-fisheye:fov=200,layout={layout}", "equirect", size=(2048, 1024))
    for blend in ({}, {"feather": 20}):
        got = pp.stitch_panorama(str(rig), size=(2048, 1024), **blend)
        ref = expected if not blend else pp.convert(frame, f"dual-fisheye:fov=200,layout={layout},feather=20",
                                                    "equirect", size=(2048, 1024))
        assert (got[..., 3] == 255).all()
        diff = np.abs(got[..., :3].astype(int) - ref.astype(int))
        print(f"{layout} {blend or 'whole overlap'}: rig against dual-fisheye: max {diff.max()} LSB, "
              f"{(diff > 0).mean():.2%} differ")
        assert diff.max() <= 1
    # The deliberate mistake: the back lens not turned round.
    bad = write_rig(tmp_path / "bad.yaml", [lenses[0], {**lenses[1], "yaw": 0}])
    got = pp.stitch_panorama(str(bad), size=(2048, 1024))
    assert np.abs(got[..., :3].astype(int) - expected.astype(int)).max() > 50


def test_three_and_four_lens_rigs_rebuild_the_scene_as_well_as_dual_fisheye(tmp_path):
    size = (1024, 512)
    want = truth(size)
    per_degree = 512 / 200  # the dual fisheye's lens pixels per degree of field
    frame = render("dual-fisheye:fov=200", (1024, 512))
    dual = pp.convert(frame[..., :3], "dual-fisheye:fov=200", "equirect", size=size)
    results = {"dual-fisheye": psnr(dual, want)}
    rigs = {"3 lenses": [(220, 0, 0), (220, 120, 0), (220, 240, 0)],
            "4 lenses": [(180, 0, 30), (180, 90, -30), (180, 180, 30), (180, 270, -30)]}
    for name, poses in rigs.items():
        lenses = []
        for k, (fov, yaw, pitch) in enumerate(poses):
            side = int(round(fov * per_degree))
            # (RGB, black outside the image circle, as the dual fisheye's frame and cameras' files.)
            pp.write(str(tmp_path / f"{k}.tif"), render(f"fisheye:fov={fov}", (side, side), yaw, pitch)[..., :3],
                     overwrite=True)
            lenses.append({"spec": f"fisheye:fov={fov}", "input": f"{k}.tif", "yaw": yaw, "pitch": pitch})
        rig = write_rig(tmp_path / "rig.yaml", lenses)
        for blend in ({}, {"blend": "multiband"}):
            got = pp.stitch_panorama(str(rig), size=size, **blend)
            assert (got[..., 3] > 0).all()
            results[f"{name} {blend.get('blend', 'feather')}"] = psnr(got[..., :3], want)
    print("PSNR against the analytic scene: " + ", ".join(f"{k} {v:.2f} dB" for k, v in results.items()))
    for k, v in results.items():
        assert v >= results["dual-fisheye"] - 0.1, k
    # The deliberate mistake: the 4-lens rig's lenses with their pitches swapped.
    lenses = [{**lens, "pitch": -lens["pitch"]} for lens in lenses]
    got = pp.stitch_panorama(str(write_rig(tmp_path / "bad.yaml", lenses)), size=size)
    assert psnr(got[..., :3], want) < results["dual-fisheye"] - 10


def test_a_template_rig_takes_other_frames(tmp_path):
    lenses = [{"spec": "fisheye:fov=200", "input": "f.png", "rect": "256x256+0+0"},
              {"spec": "fisheye:fov=200", "input": "f.png", "rect": "256x256+256+0", "yaw": 180}]
    rig = write_rig(tmp_path / "rig.yaml", lenses)
    frames = []
    for k, gain in enumerate((0.5, 1.0)):
        frames.append(str(tmp_path / f"frame{k}.png"))
        pp.write(frames[-1], (render("dual-fisheye:fov=200", (512, 256))[..., :3] * gain * 255).astype(np.uint8))
    a = pp.stitch_panorama(str(rig), images=frames[0], size=(512, 256))
    b = pp.stitch_panorama(str(rig), images=frames[1], size=(512, 256))
    # The same weights in both frames: the second is twice the first (within rounding).
    assert np.abs(b[..., :3].astype(int) - 2 * a[..., :3].astype(int)).max() <= 3
    subprocess.run([CLI, "stitch", str(rig), str(tmp_path / "p.jpg"), "--images", frames[1], "--size", "512x256",
                    "--quiet"], check=True)
    assert pp.read(str(tmp_path / "p.jpg")).shape == (256, 512, 3)


def _video(path, frames, rate=10, audio=False):
    """RGB frames (N x H x W x 3 uint8) as a lossless video (FFV1 in Matroska: decoded exactly)."""
    import shutil
    ffmpeg = shutil.which("ffmpeg")
    h, w = frames.shape[1:3]
    cmd = [ffmpeg, "-v", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", f"{w}x{h}", "-r", str(rate),
           "-i", "-"]
    if audio:
        cmd += ["-f", "lavfi", "-i", f"sine=d={len(frames) / rate}", "-c:a", "aac", "-shortest"]
    subprocess.run(cmd + ["-c:v", "ffv1", "-pix_fmt", "bgr0", str(path)], input=frames.tobytes(), check=True)
    return str(path)


def _frame_file(d, frame, k):
    path = str(d / f"frame{k}.png")
    pp.write(path, frame, overwrite=True)
    return path


def _decoded(path):
    av = pytest.importorskip("av")
    with av.open(str(path)) as c:
        return [f.to_ndarray(format="rgb24") for f in c.decode(video=0)]


@pytest.mark.skipif(__import__("shutil").which("ffmpeg") is None, reason="FFmpeg's command makes the clips")
def test_a_dual_fisheye_video_through_a_rig_is_the_equirect_video(tmp_path):
    """A 360 camera's dual-fisheye video (one frame shared by two lenses) to an equirect video:
    each frame the dual-fisheye conversion of its input frame (within the output's encoding), the
    audio kept; inputs out of step refused, nothing written."""
    src = pp.read(str(JORDAN))[::8, ::8]
    frames = np.stack([pp.convert(src, "equirect", "dual-fisheye:fov=200", size=(256, 128), yaw=12 * k)
                       for k in range(6)])
    clip = _video(tmp_path / "dual.mkv", frames, audio=True)
    lenses = [{"spec": "fisheye:fov=200", "input": "dual.mkv", "rect": "128x128+0+0"},
              {"spec": "fisheye:fov=200", "input": "dual.mkv", "rect": "128x128+128+0", "yaw": 180}]
    rig = write_rig(tmp_path / "rig.yaml", lenses)
    r = subprocess.run([CLI, "stitch", str(rig), str(tmp_path / "pano.mp4"), "--size", "256x128"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    got = _decoded(tmp_path / "pano.mp4")
    assert len(got) == len(frames)
    worst = min(psnr(g / 255, pp.convert(f, "dual-fisheye:fov=200", "equirect", size=(256, 128)) / 255)
                for g, f in zip(got, frames))
    wrong = psnr(got[0] / 255, pp.convert(frames[3], "dual-fisheye:fov=200", "equirect", size=(256, 128)) / 255)
    print(f"video rig against dual-fisheye frame by frame: worst PSNR {worst:.1f} dB (another frame: {wrong:.1f} dB)")
    assert worst > 30 and wrong < worst - 5
    streams = subprocess.run(["ffprobe", "-v", "error", "-show_entries", "stream=codec_type", "-of", "csv=p=0",
                              str(tmp_path / "pano.mp4")], capture_output=True, text=True, check=True).stdout.split()
    assert sorted(s.strip(",") for s in streams) == ["audio", "video"]
    # A template project's images as videos (--images): the same panorama video as the rig's.
    lines = ['p f2 w256 h128 v360 E0 R0 n"TIFF_m c:NONE r:CROP"\nm i2\n']
    views = []
    for k, yaw in enumerate((0, 120, 240)):
        views.append(np.stack([pp.convert(f, "dual-fisheye:fov=200", "panotools:lens=rectilinear,hfov=130",
                                          size=(160, 120), yaw=yaw) for f in frames]))
        pp.write(str(tmp_path / f"t{k}.png"), views[-1][0])
        lines.append(f'i w160 h120 f0 v130 r0 p0 y{yaw} n"t{k}.png"\n')
    (tmp_path / "t.pto").write_text("".join(lines))
    clips = [_video(tmp_path / f"t{k}.mkv", v) for k, v in enumerate(views)]
    r = subprocess.run([CLI, "stitch", str(tmp_path / "t.pto"), str(tmp_path / "t.mp4"), "--images", *clips],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    got = _decoded(tmp_path / "t.mp4")
    assert len(got) == len(frames)
    for k in (0, 5):
        still = pp.stitch_panorama(str(tmp_path / "t.pto"), images=[_frame_file(tmp_path, v[k], j)
                                                                    for j, v in enumerate(views)])
        assert psnr(got[k] / 255, still[..., :3] / 255) > 30
    # Two videos out of step: one frame short; another rate.
    lenses = [{**lenses[0], "input": "a.mkv"}, {**lenses[1], "input": "b.mkv"}]
    rig = write_rig(tmp_path / "two.yaml", lenses)
    _video(tmp_path / "a.mkv", frames)
    for b, rate, needle in ((frames[:5], 10, "5 frames"), (frames, 12, "runs at 12/1 fps")):
        _video(tmp_path / "b.mkv", b, rate=rate)
        r = subprocess.run([CLI, "stitch", str(rig), str(tmp_path / "out.mp4"), "--size", "256x128"],
                           capture_output=True, text=True)
        assert r.returncode == 1 and needle in r.stderr and len(r.stderr.strip().splitlines()) == 1, r.stderr
        assert not (tmp_path / "out.mp4").exists()


@pytest.mark.skipif(__import__("shutil").which("ffmpeg") is None, reason="FFmpeg's command makes the clips")
def test_video_rigs_refuse_what_they_cannot_make(tmp_path):
    _video(tmp_path / "v.mkv", np.zeros((3, 64, 128, 3), np.uint8))
    pp.write(str(tmp_path / "i.png"), np.zeros((64, 128, 3), np.uint8))
    video = write_rig(tmp_path / "video.yaml", [{"spec": "equirect", "input": "v.mkv"}])
    mixed = write_rig(tmp_path / "mixed.yaml", [{"spec": "equirect", "input": "i.png"},
                                               {"spec": "equirect", "input": "v.mkv", "yaw": 90}])
    image = write_rig(tmp_path / "image.yaml", [{"spec": "equirect", "input": "i.png"}])
    cases = [(video, "o.jpg", [], "the inputs are videos (", "give a video output"),
             (video, "o.mp4", ["--quality", "50"], "--quality, --subsampling, --depth and --compression are for images", ""),
             (video, "o.mp4", ["--depth", "uint16"], "are for images", ""),
             (mixed, "o.mp4", [], "is an image among videos", ""),
             (image, "o.mp4", [], "output ", "is a video: its inputs are images"),
             (video, "v.mkv", ["--overwrite"], "is an input", "")]
    for rig, out, args, a, b in cases:
        before = sorted(p.name for p in tmp_path.iterdir())
        r = subprocess.run([CLI, "stitch", str(rig), str(tmp_path / out), *args], capture_output=True, text=True)
        assert r.returncode == 1 and a in r.stderr and b in r.stderr, (out, args, r.stderr)
        assert len(r.stderr.strip().splitlines()) == 1, r.stderr
        assert sorted(p.name for p in tmp_path.iterdir()) == before
    # The array API takes images only.
    with pytest.raises(ValueError, match="give a video output"):
        pp.stitch_panorama(str(video))


def test_a_plan_over_frames_in_memory_is_the_files_panorama(tmp_path):
    """pp.StitchPlan: a rig planned once, then frames (arrays) blended call after call, each the
    panorama stitch_panorama makes from files holding the same frames; shapes kept; a template
    project's images as arrays too."""
    src = pp.read(str(JORDAN))[::8, ::8]
    lenses = [{"spec": "fisheye:fov=200", "input": "f.png", "rect": "128x128+0+0"},
              {"spec": "fisheye:fov=200", "input": "f.png", "rect": "128x128+128+0", "yaw": 180}]
    rig = write_rig(tmp_path / "rig.yaml", lenses)
    for blend in ({}, {"blend": "multiband"}):
        plan = pp.StitchPlan(str(rig), size=(256, 128), **blend)
        for k in range(3):
            frame = pp.convert(src, "equirect", "dual-fisheye:fov=200", size=(256, 128), yaw=40 * k)
            pp.write(str(tmp_path / "f.png"), frame, overwrite=True)
            got = plan([frame])
            assert np.array_equal(got, pp.stitch_panorama(str(rig), size=(256, 128), **blend)), (blend, k)
        assert plan.canvas == (256, 128)
    with pytest.raises(ValueError, match=r"frames\[0\]: 128x64 x 3 uint8 where the plan's is 256x128"):
        plan([frame[::2, ::2]])
    with pytest.raises(ValueError, match="2 arrays for a plan of 1 inputs"):
        plan([frame, frame])
    with pytest.raises(ValueError, match="arrays: 2 for a rig of 1 inputs"):
        pp.StitchPlan(str(rig), size=(256, 128))([frame, frame])
    # A template project: its images as arrays.
    lines = ['p f2 w256 h128 v360 E0 R0 n"TIFF_m c:NONE r:CROP"\nm i5\n']
    views = []
    for k, yaw in enumerate((0, 80, 160)):
        views.append(pp.convert(src, "equirect", "panotools:lens=rectilinear,hfov=100", size=(160, 120), yaw=yaw))
        pp.write(str(tmp_path / f"v{k}.png"), views[-1])
        lines.append(f'i w160 h120 f0 v100 r0 p0 y{yaw} n"v{k}.png"\n')
    (tmp_path / "t.pto").write_text("".join(lines))
    got = pp.StitchPlan(str(tmp_path / "t.pto"))(views)
    assert np.array_equal(got, pp.stitch_panorama(str(tmp_path / "t.pto")))


def test_a_crop_circle_keeps_only_its_circle(tmp_path):
    """circle: CX CY R keeps the lens's pixels inside it: a white ring outside radius 58 of a
    fisheye's gray image shows in the panorama without the circle, not at all with it."""
    side = 128
    yy, xx = np.mgrid[:side, :side] + 0.5
    ring = np.hypot(xx - 64, yy - 64) > 58
    image = np.full((side, side, 3), 100, np.uint8)
    image[ring] = 255
    pp.write(str(tmp_path / "a.png"), image)
    lens = {"spec": "fisheye:fov=200", "input": "a.png"}
    back = {"spec": "fisheye:fov=200", "input": "b.png", "yaw": 180}
    pp.write(str(tmp_path / "b.png"), np.full((side, side, 3), 100, np.uint8))
    plain = pp.stitch_panorama(str(write_rig(tmp_path / "plain.yaml", [lens, back])), size=(256, 128))
    cut = pp.stitch_panorama(str(write_rig(tmp_path / "cut.yaml", [{**lens, "circle": "64 64 56"}, back])),
                             size=(256, 128))
    assert plain[..., :3].max() > 130  # (the ring weighs little: it lies near the lens's edge)
    assert cut[..., :3].max() <= 101 and (cut[..., 3] == 255).all()
    # A circle and a crop at once, and a centre outside the image, are refused.
    for extra, needle in (({"circle": "64 64 50", "crop": "10x10+0+0"}, "has a crop and a circle"),
                          ({"circle": "200 64 50"}, "circle centre 200"), ({"circle": "64 64 0"}, "radius over 0")):
        rig = write_rig(tmp_path / "bad.yaml", [{**lens, **extra}, back])
        with pytest.raises(ValueError, match=needle):
            pp.stitch_panorama(str(rig), size=(256, 128))
