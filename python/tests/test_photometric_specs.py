"""A source spec's photometric keys (response, ev, wb, vignetting, vignetting_centre, flat_field;
a two-lens frame's ev2 ...) in convert, Python's arrays, rigs, and stitch's exposure layers:
against the truth of synthetic scenes (Hugin's camera model run forward here) and against nona.

The camera (Hugin's ResponseTransform): code = R(L * 2^(E - ev) * V(r) * wb), so the correction
R_out(R^-1(code) * 2^(ev - E) / V / wb) gives back R_out(L) at the output's exposure E.
"""
import shutil
import subprocess

import numpy as np
import pytest

import panoproj as pp
from test_stitch import CLI, JORDAN
from test_stitch_photometry import CAMERA, photometry, project, response, to_codes, vignetting

F0 = (0, 0, 0, 0, 0)  # EMoR's mean curve: the default response of integer images


def to_linear(codes, p):
    """R^-1 by the table's piecewise-linear inverse (the table is increasing for these curves)."""
    return np.interp(codes, response(p), np.arange(1024) / 1023)


def spec_of(p):
    return "/".join(str(v) for v in p)


def lens_codes(linear, p, ev, wb, vig, shift, depth=np.uint16):
    """A lens's recorded codes of linear light (H x W x 3) at exposure ev (the output's E = 0)."""
    h, w = linear.shape[:2]
    v = vignetting(w, h, vig, shift)[..., None]
    light = linear * 2.0 ** -ev * v * np.array([wb[0], 1, wb[1]])
    codes = to_codes(light, p)
    top = np.iinfo(depth).max
    return np.round(codes * top).astype(depth)


def test_a_vignetted_exposure_shifted_flat_field_comes_out_flat(tmp_path):
    """A uniform scene seen by a vignetted fisheye at +1.5 EV with white balance comes out flat
    (in linear light) after convert with the lens's keys; without the vignetting it does not."""
    w = h = 640
    vig, shift, wb, ev = (1, -0.35, 0.1, -0.02), (25, -15), (1.2, 0.8), 1.5
    src = lens_codes(np.full((h, w, 3), 0.3), CAMERA, ev, wb, vig, shift)
    pp.write(str(tmp_path / "lens.png"), src)
    keys = (f"response={spec_of(CAMERA)},ev={ev},wb={wb[0]}/{wb[1]},vignetting={spec_of(vig)},"
            f"vignetting_centre={shift[0]}/{shift[1]}")
    out = tmp_path / "view.png"
    subprocess.run([CLI, "convert", str(tmp_path / "lens.png"), str(out), "--from", f"fisheye:fov=180,{keys}",
                    "--to", "pinhole:hfov=110,ev=0", "--size", "800x800", "--quiet"], check=True)
    got = to_linear(pp.read(str(out)).astype(np.float64) / 65535, CAMERA)
    spread = got.max() / got.min() - 1
    print(f"16-bit fisheye, vignetted, +{ev} EV, white balance: linear light {got.min():.5f} .. {got.max():.5f} "
          f"(flat within {spread:.3%}; the scene is 0.3)")
    assert abs(np.median(got) / 0.3 - 1) < 0.005 and spread < 0.005
    # The same in memory, from float samples (response linear), through Python's convert.
    linear = src.astype(np.float32) / 65535
    linear = to_linear(linear, CAMERA).astype(np.float32)
    view = pp.convert(linear, f"fisheye:fov=180,{keys.replace(spec_of(CAMERA), 'linear')}", "pinhole:hfov=110,ev=0",
                      size=(800, 800))
    assert view.dtype == np.float32
    fspread = view.max() / view.min() - 1
    print(f"float fisheye (response=linear): {view.min():.5f} .. {view.max():.5f} (flat within {fspread:.3%})")
    assert abs(np.median(view) / 0.3 - 1) < 0.005 and fspread < 0.005
    # The deliberate mistake: the vignetting left in.
    plain = keys.split(",vignetting=")[0]
    subprocess.run([CLI, "convert", str(tmp_path / "lens.png"), str(out), "--from", f"fisheye:fov=180,{plain}",
                    "--to", "pinhole:hfov=110,ev=0", "--size", "800x800", "--quiet", "--overwrite"], check=True)
    bad = to_linear(pp.read(str(out)).astype(np.float64) / 65535, CAMERA)
    assert bad.max() / bad.min() - 1 > 0.1


def test_a_rig_lenss_flat_field_divides_out_its_vignetting(tmp_path):
    """A rig lens's flat_field: a measured field (any scale, colour averaged) in place of the
    polynomial; the same without it stays vignetted."""
    w, h = 320, 240
    field = vignetting(w, h, (1, -0.4, 0.05, 0), (10, 5))
    pp.write(str(tmp_path / "flat.tif"), np.repeat((0.7 * field)[..., None], 3, -1).astype(np.float32))
    pp.write(str(tmp_path / "lens.png"), lens_codes(np.full((h, w, 3), 0.25), F0, 0, (1, 1), (1, -0.4, 0.05, 0),
                                                    (10, 5)))
    for flat, flat_within in ((", flat_field: flat.tif", 0.005), ("", None)):
        (tmp_path / "rig.yaml").write_text(f"- {{spec: 'pinhole:hfov=90', input: lens.png{flat}}}\n")
        pano = pp.stitch_panorama(str(tmp_path / "rig.yaml"), to="pinhole:hfov=80", size=(320, 240))
        lin = to_linear(pano[..., :3].astype(np.float64) / 65535, F0)[pano[..., 3] > 0]
        print(f"flat field{flat or ' (none)'}: {lin.min():.5f} .. {lin.max():.5f}")
        if flat_within:
            assert lin.max() / lin.min() - 1 < flat_within
        else:
            assert lin.max() / lin.min() - 1 > 0.2


def dual_frames(tmp_path):
    """A dual-fisheye frame of a real panorama (16-bit codes of EMoR's mean curve), and the same
    with lens 1 (the right half) a stop brighter."""
    src = pp.read(str(JORDAN))[::4, ::4]
    frame = pp.convert(src, "equirect", "dual-fisheye:fov=200", size=(1024, 512), interp="bicubic")
    codes = frame.astype(np.float64) / 255
    brighter = codes.copy()
    brighter[:, 512:] = to_codes(2 * to_linear(codes[:, 512:], F0), F0)
    return [np.round(c * 65535).astype(np.uint16) for c in (codes, brighter)]


def band_ratios(got, ref, width=1024):
    """Median linear ratio got/ref in lens 0's part, the blend band and lens 1's part of an equirect
    (lens 0 looks at longitude 0, the band around +-90 degrees; 200-degree lenses: +-10 degrees)."""
    lon = (np.arange(width) + 0.5) / width * 360 - 180
    a, b = to_linear(got / 65535, F0), to_linear(ref / 65535, F0)
    ok = (b > 0.02) & (b < 0.45) & (a > 0.01)
    rows = slice(got.shape[0] // 4, 3 * got.shape[0] // 4)
    parts = {"lens 0": np.abs(lon) < 70, "band": (np.abs(np.abs(lon) - 90) < 9), "lens 1": np.abs(lon) > 110}
    return {k: float(np.median((a / np.where(ok, b, 1))[rows][:, m][ok[rows][:, m]])) for k, m in parts.items()}


def test_a_360_cameras_two_exposures_meet_without_a_step(tmp_path):
    """dual-fisheye with ev2: lens 1 recorded a stop brighter comes out as the frame without the
    difference, in its own part and across the blend band (convert); as a rig of two lenses (stitch)
    the same. Without ev2 the step stays."""
    even, uneven = dual_frames(tmp_path)
    ref = pp.convert(even, "dual-fisheye:fov=200", "equirect", size=(1024, 512))
    got = pp.convert(uneven, "dual-fisheye:fov=200,ev2=-1", "equirect:ev=0", size=(1024, 512))
    r = band_ratios(got.astype(np.float64), ref.astype(np.float64))
    print("dual-fisheye, lens 1 +1 EV, ev2=-1: linear ratio to the even frame " +
          ", ".join(f"{k} {v:.4f}" for k, v in r.items()))
    assert all(abs(v - 1) < 0.005 for v in r.values())
    # The default output exposure: the lenses' mean (each half a stop off the even frame).
    mid = band_ratios(pp.convert(uneven, "dual-fisheye:fov=200,ev2=-1", "equirect", size=(1024, 512))
                      .astype(np.float64), ref.astype(np.float64))
    assert all(abs(v / 2 ** 0.5 - 1) < 0.005 for v in mid.values()), mid
    bad = band_ratios(pp.convert(uneven, "dual-fisheye:fov=200", "equirect", size=(1024, 512)).astype(np.float64),
                      ref.astype(np.float64))
    assert bad["lens 1"] > 1.8 and abs(bad["lens 0"] - 1) < 0.005
    # The rig: each lens its own keys.
    pp.write(str(tmp_path / "frame.png"), uneven)
    (tmp_path / "rig.yaml").write_text(
        "lenses:\n"
        "  - {spec: 'fisheye:fov=200,ev=0', input: frame.png, rect: 512x512+0+0}\n"
        "  - {spec: 'fisheye:fov=200,ev=-1', input: frame.png, rect: 512x512+512+0, yaw: 180}\n")
    pano = pp.stitch_panorama(str(tmp_path / "rig.yaml"), size=(1024, 512), exposure=0)
    rr = band_ratios(pano[..., :3].astype(np.float64), ref.astype(np.float64))
    print("the same as a rig (stitch): " + ", ".join(f"{k} {v:.4f}" for k, v in rr.items()))
    assert all(abs(v - 1) < 0.005 for v in rr.values())


@pytest.mark.skipif(shutil.which("ffmpeg") is None, reason="FFmpeg's command makes the clip")
def test_a_rig_of_a_video_corrects_each_frame(tmp_path):
    """The two-exposure dual fisheye as a video (8-bit, lossless) through a rig: every frame's
    panorama steps by under 0.5% across the band (H.264 moves all of it by ~1.5%)."""
    from test_stitch_rig import _decoded, _video
    even, uneven = [np.round(f / 257.0).astype(np.uint8) for f in dual_frames(tmp_path)]
    clip = _video(tmp_path / "dual.mkv", np.stack([uneven] * 2))
    (tmp_path / "rig.yaml").write_text(
        "lenses:\n"
        f"  - {{spec: 'fisheye:fov=200', input: {clip}, rect: 512x512+0+0}}\n"
        f"  - {{spec: 'fisheye:fov=200,ev=-1', input: {clip}, rect: 512x512+512+0, yaw: 180}}\n")
    subprocess.run([CLI, "stitch", str(tmp_path / "rig.yaml"), str(tmp_path / "pano.mp4"), "--size", "1024x512",
                    "--exposure", "0", "--quiet"], check=True)
    ref = pp.convert(even, "dual-fisheye:fov=200", "equirect", size=(1024, 512)).astype(np.float64) * 257
    frames = _decoded(tmp_path / "pano.mp4")
    assert len(frames) == 2
    for f in frames:
        r = band_ratios(f.astype(np.float64) * 257, ref)
        print("a rig of the video, each frame (H.264): " + ", ".join(f"{k} {v:.4f}" for k, v in r.items()))
        assert max(r.values()) / min(r.values()) < 1.005 and all(abs(v - 1) < 0.03 for v in r.values())


@pytest.mark.skipif(shutil.which("ffmpeg") is None, reason="FFmpeg's command makes the clip")
def test_a_videos_frames_take_the_keys_as_images_and_as_a_video(tmp_path):
    """A video with photometric keys is decoded as RGB (a response needs RGB, not its planes):
    its frames as images are the truth within 1 LSB; as a video, those images made a video."""
    from test_stitch_rig import _decoded, _video
    frames = np.stack([pp.read(str(JORDAN))[::16, ::16]] * 2)
    clip = _video(tmp_path / "clip.mkv", frames)
    want = to_codes(2 * to_linear(frames[0] / 255.0, F0), F0)
    subprocess.run([CLI, "convert", clip, str(tmp_path / "f_{n}.png"), "--from", "equirect:ev=1",
                    "--to", "equirect:ev=0", "--quiet"], check=True)
    got = pp.read(str(tmp_path / "f_0.png")).astype(np.float64) / 255
    assert np.abs(got - want).max() <= 1.01 / 255
    subprocess.run([CLI, "convert", clip, str(tmp_path / "o.mkv"), "--codec", "ffv1", "--from", "equirect:ev=1",
                    "--to", "equirect:ev=0", "--quiet"], check=True)
    # The same frames corrected as images, then made a video: the same encoding of the same RGB.
    subprocess.run([CLI, "convert", tmp_path / "f_0.png", tmp_path / "f_1.png", str(tmp_path / "i.mkv"), "--codec",
                    "ffv1", "--to", "equirect", "--quiet"], check=True)
    out, ref = _decoded(tmp_path / "o.mkv"), _decoded(tmp_path / "i.mkv")
    assert len(out) == 2 and all((a == b).all() for a, b in zip(out, ref))
    d = np.abs(out[1] / 255.0 - want) * 255
    print(f"a video's frames through ev=1 -> ev=0, FFV1 out: the corrected images' video exactly; "
          f"{np.median(d):.1f} LSB (median) from the truth after its 4:2:0")


# nona's exposure layers: four images in two groups (0 and 0.49 EV; 1.2 and 1.0 EV).
EVS = (0.0, 0.49, 1.2, 1.0)
POSES = ((20, 10, 5), (60, -5, -3), (100, 0, 0), (140, 0, 0))


@pytest.mark.skipif(shutil.which("nona") is None, reason="nona (hugin-tools) is not installed")
def test_exposure_layers_are_nonas(tmp_path):
    pytest.importorskip("OpenImageIO")
    from test_stitch import erode, on_canvas
    pp.write(str(tmp_path / "img.png"), np.ascontiguousarray(pp.read(str(JORDAN))[700:1100, 1500:2100]))
    images = [("img.png", (600, 400), 70, pose, photometry(CAMERA, ev, 1.1, 0.9, (1, -0.2, 0, 0), (5, 0)))
              for ev, pose in zip(EVS, POSES)]
    (tmp_path / "t.pto").write_text(project(images))
    subprocess.run(["nona", "-p", "FLOAT", "--create-exposure-layers", "-o", str(tmp_path / "n_"),
                    str(tmp_path / "t.pto")], check=True, capture_output=True)
    r = subprocess.run([CLI, "stitch", str(tmp_path / "t.pto"), str(tmp_path / "q_"), "--create-exposure-layers",
                        "--depth", "float", "--engine", "reference"], check=True, capture_output=True, text=True)
    assert "q_0001.tif: 800x400, images 2, 3 at 1.2 EV" in r.stdout
    ns, qs = sorted(tmp_path.glob("n_*.tif")), sorted(tmp_path.glob("q_*.tif"))
    assert len(ns) == len(qs) == 2
    for g, (group, ev) in enumerate((((0, 1), 0.0), ((2, 3), 1.2))):
        # Where one image of the group covers (nona's own layers at the group's exposure).
        for f in tmp_path.glob("s_*"):
            f.unlink()
        subprocess.run(["nona", "-p", "FLOAT", "-m", "TIFF_m", "-e", str(ev), "-o", str(tmp_path / "s_"),
                        str(tmp_path / "t.pto")], check=True, capture_output=True)
        cover = sum((on_canvas(tmp_path / f"s_{i:04d}.tif")[0][..., 3] > 0).astype(int) for i in group)
        n, q = on_canvas(ns[g])[0], on_canvas(qs[g])[0]
        one = erode((cover == 1) & (n[..., 3] > 0) & (q[..., 3] > 0))
        d = np.abs(q[..., :3] - n[..., :3])[one]
        worst = (d - 1e-4 * np.abs(n[..., :3][one])).max()
        print(f"exposure layer {g} (images {group} at {ev} EV): max |panoproj - nona| {d.max():.2e} over "
              f"{one.sum()} pixels one image covers")
        assert worst <= 1e-4
    # The groups split where nona's do: 0.5 EV apart is another group.
    (tmp_path / "t.pto").write_text(project([images[0], ("img.png", (600, 400), 70, POSES[1],
                                                         photometry(CAMERA, 0.5, 1, 1, (1, 0, 0, 0), (0, 0)))]))
    r = subprocess.run([CLI, "stitch", str(tmp_path / "t.pto"), str(tmp_path / "e_"), "--create-exposure-layers"],
                       check=True, capture_output=True, text=True)
    assert len(list(tmp_path.glob("e_*.tif"))) == 2


def test_convert_corrects_before_sampling_and_stitch_after(tmp_path):
    """The same lens and keys through convert (corrected, then sampled) and through a one-lens rig
    (sampled, then corrected: nona's order) differ only where the response bends a sharp edge:
    the figures docs/projections.md gives. Without keys the two are the same to 1 LSB."""
    lens = pp.convert(pp.read(str(JORDAN))[::4, ::4], "equirect", "fisheye:fov=190", size=(512, 512))
    pp.write(str(tmp_path / "lens.png"), lens)
    rows = []
    for keys, ev in (("", 0), (",ev=-1", 0), (",vignetting=1/-0.3/0.1/-0.05,vignetting_centre=20/-10", 0),
                     (",wb=1.1/0.9", 0)):
        (tmp_path / "rig.yaml").write_text(f"- {{spec: 'fisheye:fov=190{keys}', input: lens.png}}\n")
        a = pp.stitch_panorama(str(tmp_path / "rig.yaml"), size=(1024, 512), exposure=ev)
        b = pp.convert(lens, f"fisheye:fov=190{keys}", f"equirect:ev={ev}", size=(1024, 512), antialias="off")
        d = np.abs(a[..., :3].astype(int) - b.astype(int))[a[..., 3] == 255]
        rows.append((keys or "none", d.max(), np.percentile(d, 99.9), (d > 1).mean()))
        print(f"keys {rows[-1][0]}: convert against a one-lens rig: max {d.max()} LSB, 99.9% within "
              f"{rows[-1][2]:.0f}, {rows[-1][3]:.2%} over 1 LSB")
    assert rows[0][1] <= 1
    assert all(r[3] < 0.05 for r in rows)


def test_a_calibration_file_carries_the_keys(tmp_path):
    """@lens.yaml (a flat mapping, as convert reads calibrations) with the photometric keys gives
    the spec string's output, to the byte."""
    src = lens_codes(np.full((240, 240, 3), 0.3), CAMERA, 0.5, (1.1, 0.9), (1, -0.3, 0, 0), (4, -2), np.uint8)
    (tmp_path / "lens.yaml").write_text("projection: fisheye\nfov: 180\nresponse: 0.5/-0.3/0.2/0.1/-0.05\nev: 0.5\n"
                                        "wb: 1.1/0.9\nvignetting: 1/-0.3\nvignetting_centre: 4/-2\n")
    a = pp.convert(src, f"@{tmp_path / 'lens.yaml'}", "equirect:ev=0", size=(256, 128))
    b = pp.convert(src, "fisheye:fov=180,response=0.5/-0.3/0.2/0.1/-0.05,ev=0.5,wb=1.1/0.9,vignetting=1/-0.3,"
                        "vignetting_centre=4/-2", "equirect:ev=0", size=(256, 128))
    plain = pp.convert(src, "fisheye:fov=180", "equirect", size=(256, 128))
    assert (a == b).all() and not (a == plain).all()


def test_views_and_tiles_take_the_keys(tmp_path):
    """The folder jobs convert through the same Converter: a source's vignetting is divided out of
    every view and tile (brighter than without), as convert's own view of it."""
    pano = tmp_path / "pano.jpg"
    pp.write(str(pano), pp.read(str(JORDAN))[::4, ::4])
    for job, extra in (("views", []), ("tiles", [])):
        for name, spec in (("plain", "equirect"), ("keys", "equirect:vignetting=1/-0.5")):
            subprocess.run([CLI, job, str(pano), str(tmp_path / f"{job}_{name}"), "--from", spec, "--quiet", *extra],
                           check=True)
        plain = sorted((tmp_path / f"{job}_plain").rglob("*.jpg"))
        assert plain
        for f in plain:
            g = tmp_path / f"{job}_keys" / f.relative_to(tmp_path / f"{job}_plain")
            assert pp.read(str(g)).astype(float).mean() > pp.read(str(f)).astype(float).mean() + 1, g
    front = pp.read(str(tmp_path / "views_keys" / "images" / "pano_front.jpg"))
    want = pp.convert(pp.read(str(pano)), "equirect:vignetting=1/-0.5", "pinhole:hfov=90", size=front.shape[1::-1])
    assert np.abs(front.astype(int) - want.astype(int)).mean() < 2  # (JPEG both ways)
