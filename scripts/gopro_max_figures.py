#!/usr/bin/env python3
"""The GoPro MAX figures of docs/gopro_max.md, on the real frames in samples/gopro_max/:
  - the layout measured: where each outer face's band repeats (the lenses' copies of one ray);
  - the band difference before blending: the two lenses' pixels of the same rays, per seam;
  - seams after conversion: the mean absolute difference of 9x9-box-filtered luma across each of
    the four seams (2 px either side) beside the same on lines 100 px into the face;
  - the 3K equirect against max2sphere's (its 2272x1136, 2x2 antialiasing, samples at pixel
    corners: a quarter pixel left of and below panoproj's centres), PSNR as is and shifted, overall
    and in 64-px bands around the seams; crops where the two differ most (--crops DIR).
Usage: gopro_max_figures.py [--cli PANOPROJ] [--crops DIR] [--json OUT]
The Python tests (python/tests/test_gopro_max.py) assert on the same functions."""
import argparse
import json
import os
import pathlib
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image

ROOT = pathlib.Path(__file__).resolve().parents[1]
FRAMES = ROOT / "samples" / "gopro_max"
# mode: (strip 0:0, strip 0:5, outer face S, centre face C, band D)
PAIRS = {
    "5.6k": ("5_6k_track0_GS018421_1.jpg", "5_6k_track5_GS018421_1.jpg", 1376, 1344, 64),
    "3k": ("3k_track0_GS018423_1.jpg", "3k_track5_GS018423_1.jpg", 768, 736, 32),
}
PEER_3K = FRAMES / "3k_STITCHED_GS018423_1.jpg"
# The outer faces, by strip and first column: the seam down the middle of each.
SEAMS = (("left", 0, "first"), ("right", 0, "last"), ("down", 1, "first"), ("up", 1, "last"))
# Cube faces of panoproj's 6x1 strip (f r b l u d) and how the seam crosses them.
CUBE_SEAMS = (("left", 3, "vertical"), ("right", 1, "vertical"), ("up", 4, "horizontal"), ("down", 5, "horizontal"))


def luma(rgb):
    rgb = np.asarray(rgb, dtype=np.float64)
    return rgb[..., 0] * 0.299 + rgb[..., 1] * 0.587 + rgb[..., 2] * 0.114


def load(path):
    return np.asarray(Image.open(path).convert("RGB"), dtype=np.float64)


def box9(a):
    """The 9x9 box mean (edges: the window clipped)."""
    def along(v, axis):
        c = np.cumsum(np.pad(v, [(4, 5) if k == axis else (0, 0) for k in range(v.ndim)], mode="edge"), axis=axis)
        hi = np.take(c, np.arange(9, c.shape[axis]), axis=axis)
        lo = np.take(c, np.arange(0, c.shape[axis] - 9), axis=axis)
        return (hi - lo) / 9
    return along(along(a, 0), 1)


def psnr(a, b, mask=None):
    d = (a - b) ** 2
    if mask is not None:
        d = d[mask]
    return 10 * np.log10(255.0 ** 2 / d.mean())


def convert(cli, inputs, out, to, size=None, src="gopro-max"):
    cmd = [cli, "convert", *map(str, inputs), str(out), "--from", src, "--to", to, "--overwrite"]
    if size:
        cmd += ["--size", size]
    subprocess.run(cmd, check=True, capture_output=True, text=True)


def strip_x0(S, C, which):
    return 0 if which == "first" else S + C


def band_repeat(mode):
    """Per seam, the column offset at which the band's content repeats (best normalized
    correlation of 12-px column strips in the half by the outer edge, searched 16..S/6)."""
    a, b, S, C, D = PAIRS[mode]
    strips = [luma(load(FRAMES / a)), luma(load(FRAMES / b))]
    out = {}
    for name, s, which in SEAMS:
        L = strips[s]
        H = L.shape[0]
        mid = strip_x0(S, C, which) + S // 2
        best = []
        for x0 in (mid - 36, mid - 26, mid - 16):
            rows = slice(int(0.15 * H), int(0.85 * H))
            p = L[rows, x0:x0 + 12]
            p = (p - p.mean()) / (p.std() + 1e-9)
            score = []
            for d in range(16, S // 6):
                q = L[rows, x0 + d:x0 + d + 12]
                score.append(((p * (q - q.mean()) / (q.std() + 1e-9)).mean(), d))
            best.append(max(score))
        out[name] = {"offsets": [d for _, d in best], "correlations": [round(c, 3) for c, _ in best]}
    return out


def band_differences(mode):
    """Per seam, the mean absolute luma difference of the two lenses' copies of the band's rays:
    column x of the outer-edge half and x + D of the centre-side half, over the band's D columns."""
    a, b, S, C, D = PAIRS[mode]
    strips = [luma(load(FRAMES / a)), luma(load(FRAMES / b))]
    out = {}
    for name, s, which in SEAMS:
        mid = strip_x0(S, C, which) + S // 2
        L = strips[s]
        out[name] = float(np.abs(L[:, mid - D:mid] - L[:, mid:mid + D]).mean())
    return out


def seam_statistics(cube_png, face):
    """Per seam of a 6x1 cube (f r b l u d) of `face` px: the mean |B(c + 2) - B(c - 2)| of the
    9x9-box-filtered luma B across the seam's line c (the face's midline), across the lines 100 px
    into the face either side, and over the 241 lines within 120 px: their median and the share
    of them below the seam's (a seam would stand out at the top)."""
    L = luma(load(cube_png))
    out = {}
    for name, k, direction in CUBE_SEAMS:
        B = box9(L[:, k * face:(k + 1) * face])
        if direction == "horizontal":
            B = B.T
        m = face // 2
        profile = np.array([np.abs(B[:, c + 2] - B[:, c - 2]).mean() for c in range(m - 120, m + 121)])
        out[name] = {"seam": float(profile[120]), "inside": [float(profile[20]), float(profile[220])],
                     "median within 120 px": float(np.median(profile)), "rank": float(np.mean(profile < profile[120]))}
    return out


def shifted(rgb, dx, dy):
    """rgb resampled at positions (x + dx, y + dy) of its own pixel centres (bicubic)."""
    out = np.empty_like(rgb)
    h, w = rgb.shape[:2]
    for c in range(rgb.shape[2]):
        im = Image.fromarray(rgb[..., c].astype(np.float32), mode="F")
        out[..., c] = np.asarray(im.transform((w, h), Image.Transform.AFFINE, (1, 0, dx, 0, 1, dy),
                                              resample=Image.Resampling.BICUBIC))
    return out


def against_peer(cli, work):
    """The 3K equirect (2272x1136) against max2sphere's: PSNR overall and in the seams' 64-px bands,
    as is and with panoproj's resampled at max2sphere's sample positions (dx = -1/4, dy = +1/4)."""
    a, b, S, C, D = PAIRS["3k"]
    ours_png = pathlib.Path(work) / "panoproj_3k.png"
    convert(cli, [FRAMES / a, FRAMES / b], ours_png, "equirect", "2272x1136")
    ours, peer = load(ours_png), load(PEER_3K)
    h, w = peer.shape[:2]
    # (The edge columns and rows the shift reads past are left out of both.)
    inner = np.zeros((h, w), bool)
    inner[2:-2, 2:-2] = True
    band = np.zeros((h, w), bool)
    for x in (w // 4, 3 * w // 4):
        band[:, x - 32:x + 32] = True
    m = ours[..., 0] >= 0  # all
    results = {}
    for label, img in (("as is", ours), ("shifted", shifted(ours, -0.25, 0.25)), ("shifted the other way", shifted(ours, 0.25, -0.25))):
        results[label] = {"overall": psnr(img, peer, np.broadcast_to((inner & m)[..., None], img.shape)),
                          "seam bands": psnr(img, peer, np.broadcast_to((inner & band)[..., None], img.shape)),
                          "outside the bands": psnr(img, peer, np.broadcast_to((inner & ~band)[..., None], img.shape))}
    return results, ours_png


def worst_window(a, b, size=96):
    """The size x size window (on a grid of half its size) where luma differs most."""
    d = box9(np.abs(luma(a) - luma(b)))
    h, w = d.shape
    best = (0, 0, 0)
    for y in range(0, h - size, size // 2):
        for x in range(0, w - size, size // 2):
            v = d[y:y + size, x:x + size].mean()
            if v > best[0]:
                best = (v, x, y)
    return best


def crops(cli, work, ours_png, out_dir):
    """Full-size crops (3x enlarged, nearest) of panoproj's and max2sphere's 3K equirects and their
    luma difference (x4, grey = 0): where they differ most, and across the left seam (x = W/4)."""
    ours, peer = load(ours_png), load(PEER_3K)
    v, x, y = worst_window(shifted(ours, -0.25, 0.25), peer)
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    s = 96
    rows = []
    for cx, cy in ((x, y), (peer.shape[1] // 4 - s // 2, 560)):
        parts = [ours[cy:cy + s, cx:cx + s], peer[cy:cy + s, cx:cx + s]]
        diff = luma(parts[0]) - luma(parts[1])
        parts.append(np.repeat(np.clip(128 + 4 * diff, 0, 255)[..., None], 3, axis=2))
        rows.append(np.concatenate([np.pad(p, ((0, 4), (0, 4), (0, 0)), constant_values=255) for p in parts], axis=1))
    big = np.repeat(np.repeat(np.concatenate(rows, axis=0), 3, axis=0), 3, axis=1)
    Image.fromarray(big.astype(np.uint8)).save(out_dir / "gopro_max_vs_max2sphere.png")
    return {"most different window": [int(x), int(y), s, s], "its mean |luma difference| (box 9)": float(v),
            "seam window": [peer.shape[1] // 4 - s // 2, 560, s, s]}


def figures(cli, crop_dir=None):
    out = {"band repeat": {m: band_repeat(m) for m in PAIRS},
           "band difference before blending": {m: band_differences(m) for m in PAIRS}}
    with tempfile.TemporaryDirectory() as work:
        out["seams after conversion"], out["seams after a hard cut"] = {}, {}
        for mode, (a, b, S, C, D) in PAIRS.items():
            for key, src in (("seams after conversion", "gopro-max"), ("seams after a hard cut", "gopro-max:feather=0")):
                cube = pathlib.Path(work) / f"cube_{mode}.png"
                convert(cli, [FRAMES / a, FRAMES / b], cube, "cubemap", f"{6 * C}x{C}", src)
                out[key][mode] = seam_statistics(cube, C)
        peer, ours_png = against_peer(cli, work)
        out["3k equirect against max2sphere (PSNR, dB)"] = peer
        if crop_dir:
            out["crops"] = crops(cli, work, ours_png, crop_dir)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cli", default=os.environ.get("PANOPROJ_CLI", str(ROOT / "build" / "tools" / "panoproj")))
    ap.add_argument("--crops", help="folder for the crops (e.g. docs/gallery)")
    ap.add_argument("--json", help="also write the figures here")
    args = ap.parse_args()
    f = figures(args.cli, args.crops)
    text = json.dumps(f, indent=1, default=float)
    print(text)
    if args.json:
        pathlib.Path(args.json).write_text(text + "\n")


if __name__ == "__main__":
    sys.exit(main())
