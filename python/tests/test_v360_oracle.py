"""Cube formats against FFmpeg's v360 (a test oracle, apt's ffmpeg): where each tool samples, read
from 16-bit x and y ramps passed through both, for e -> eac (FFmpeg's EAC frame), e -> c3x2 with a
face order and turns of its own, and back; a wrong turn must fail.

v360 (Debian's FFmpeg 5.1) reads an equirect input with its pixel centres spread from -180 to +180
degrees and pole to pole, (W - 1) / W of panoproj's spacing: measured here (median 0.02 px
after that model, 0.23 px without), so the equirect-side positions are compared through it. Its
equirect output and every cube side use pixel centres as panoproj does.
"""
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import panoproj as pp

pytestmark = pytest.mark.skipif(shutil.which("ffmpeg") is None, reason="ffmpeg (v360) is not installed")

F = 192          # cube cell
W, H = 1024, 512  # equirect
K = 60.0         # ramp LSB per pixel: 1024 px x 60 < 65535


def v360(tmp: Path, image: np.ndarray, args: str, pix_fmt: str = "gray16be") -> np.ndarray:
    src, out = tmp / "in.png", tmp / "out.png"
    pp.write(str(src), image, overwrite=True)
    subprocess.run(["ffmpeg", "-v", "error", "-y", "-i", str(src), "-vf", "v360=" + args,
                    "-pix_fmt", pix_fmt, str(out)], check=True)
    return pp.read(str(out)).astype(np.float64)


def ramps(w: int, h: int):
    x = np.tile((np.arange(w) + 0.5) * K, (h, 1))
    y = np.tile(((np.arange(h) + 0.5) * K)[:, None], (1, w))
    return x.astype(np.uint16), y.astype(np.uint16)


def positions_v360(tmp: Path, w: int, h: int, args: str):
    rx, ry = ramps(w, h)
    return v360(tmp, rx, args) / K, v360(tmp, ry, args) / K


def positions_panoproj(w: int, h: int, src: str, dst: str, size):
    rx, ry = ramps(w, h)
    kw = dict(size=size, interp="bilinear", antialias="off")
    return (pp.convert(rx, src, dst, **kw).astype(np.float64) / K,
            pp.convert(ry, src, dst, **kw).astype(np.float64) / K)


def cell_interior(size, margin: float = 3):
    """Pixels of a 3x2 cube frame at least `margin` px inside their cell (taps there stay on one
    face; FFmpeg's EAC cells are within 2 px of the even grid)."""
    w, h = size
    ys, xs = np.mgrid[0:h, 0:w] + 0.5
    cw, ch = w / 3, h / 2
    return (xs % cw > margin) & (cw - xs % cw > margin) & (ys % ch > margin) & (ch - ys % ch > margin)


def e_to_cube_gap(tmp, vargs, spec, size):
    """Largest distance between v360's and panoproj's equirect sample positions (v360's spacing
    modelled), over cube pixels away from cell edges and the equirect's seam and poles."""
    fx, fy = positions_v360(tmp, W, H, vargs)
    px, py = positions_panoproj(W, H, "equirect", spec, size)
    mx, my = px * (W - 1) / W + 0.5, py * (H - 1) / H + 0.5
    inner = cell_interior(size) & (px > 4) & (px < W - 4) & (py > 4) & (py < H - 4)
    gap = np.hypot(fx - mx, fy - my)[inner]
    return float(np.median(gap)), float(gap.max())


def cube_to_e_gap(tmp, vargs, spec, size):
    """The same the other way: cube positions, away from cell edges, where an output pixel spans
    at most 2 cube pixels (near the poles the equirect spans up to 10: a hundredth of an output
    pixel's difference in v360's rays moves its position by 0.1 px there)."""
    fx, fy = positions_v360(tmp, size[0], size[1], vargs)
    px, py = positions_panoproj(size[0], size[1], spec, "equirect", (W, H))
    cw, ch = size[0] / 3, size[1] / 2
    stretch = np.maximum.reduce([np.abs(np.gradient(v, axis=a)) for v in (px, py) for a in (0, 1)])
    inner = (px % cw > 3) & (cw - px % cw > 3) & (py % ch > 3) & (ch - py % ch > 3) & (stretch <= 2)
    gap = np.hypot(fx - px, fy - py)[inner]
    return float(np.median(gap)), float(gap.max())


CASES = [
    ("output=eac", "cubemap:layout=eac,border=ffmpeg"),
    ("output=c3x2:out_forder=fbrlud:out_frot=102300", "cubemap:layout=3x2,order=fbrlud,rot=102300"),
    ("output=c3x2", "cubemap:layout=3x2,order=rludfb"),
]


@pytest.mark.parametrize("out,spec", CASES)
def test_equirect_to_cube_samples_where_v360_does(tmp_path, out, spec):
    size = (3 * F, 2 * F)
    median, worst = e_to_cube_gap(tmp_path, f"input=e:{out}:w={size[0]}:h={size[1]}:interp=linear", spec, size)
    print(f"\n[v360] e {W}x{H} -> {spec} {size[0]}x{size[1]}: median {median:.3f} px, worst {worst:.3f} px")
    assert worst <= 0.25


@pytest.mark.parametrize("out,spec", CASES)
def test_cube_to_equirect_samples_where_v360_does(tmp_path, out, spec):
    size = (3 * F, 2 * F)
    vin = out.replace("output=", "input=").replace("out_", "in_")
    median, worst = cube_to_e_gap(tmp_path, f"{vin}:output=e:w={W}:h={H}:interp=linear", spec, size)
    print(f"\n[v360] {spec} {size[0]}x{size[1]} -> e {W}x{H}: median {median:.3f} px, worst {worst:.3f} px")
    assert worst <= 0.25


def test_a_wrong_turn_fails(tmp_path):
    """The deliberate mistake: one slot turned once more than v360 turns it."""
    size = (3 * F, 2 * F)
    _, worst = e_to_cube_gap(tmp_path, f"input=e:output=c3x2:w={size[0]}:h={size[1]}:interp=linear:"
                             "out_forder=fbrlud:out_frot=102300", "cubemap:layout=3x2,order=fbrlud,rot=112300", size)
    assert worst > 10


def test_outputs_on_a_smooth_scene(tmp_path):
    """PSNR of the two tools' 8-bit outputs of the bundled panorama (reported; a bar well below)."""
    root = Path(__file__).resolve().parents[2]
    pano = pp.read(str(root / "samples/images/jordan_pond_4096x2048.jpg"))
    small = pp.convert(pano, "equirect", "equirect", size=(W, H))  # smooth: 4x down, antialiased
    size = (3 * F, 2 * F)
    for out, spec in CASES[:2]:
        a = v360(tmp_path, small, f"input=e:{out}:w={size[0]}:h={size[1]}:interp=linear", "rgb24")
        ours = pp.convert(small, "equirect", spec, size=size, interp="bilinear", antialias="off").astype(np.float64)
        inner = cell_interior(size)
        mse = np.mean((a[inner] - ours[inner]) ** 2)
        psnr = 10 * np.log10(255 ** 2 / mse)
        print(f"\n[v360] jordan pond {W}x{H} -> {spec}: PSNR {psnr:.1f} dB against v360")
        assert psnr > 30  # v360 reads the equirect at (W - 1) / W spacing: up to half a pixel apart
