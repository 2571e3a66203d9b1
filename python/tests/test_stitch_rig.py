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
