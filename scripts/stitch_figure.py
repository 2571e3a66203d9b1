#!/usr/bin/env python3
"""The pictures of docs/stitching.md: eight views of the real Jordan Pond panorama (samples/images/)
through five lens types with a b c d e g t, written as a Hugin project, their layers made by
`panoproj stitch` and blended by enblend, beside the layers' outlines on the canvas; and (--seams)
the same views each at its own gain (0.8 to 1.2: an exposure step at every seam), a crop across
seams blended by enblend, panoproj's feather and multiband, beside the truth.
Usage: stitch_figure.py [--cli PANOPROJ] [--out docs/gallery/stitch_enblend.jpg]
                        [--seams docs/gallery/stitch_seams.jpg]   (needs enblend)"""
import argparse
import pathlib
import subprocess
import tempfile

import numpy as np

import panoproj as pp

ROOT = pathlib.Path(__file__).resolve().parents[1]
VIEWS = [(0, "rectilinear", 100, 0, 0, 0), (3, "equidistant", 160, 90, 20, 5), (21, "equisolid", 170, 180, -10, -3),
         (10, "stereographic", 160, 270, 5, 2), (0, "rectilinear", 100, 45, 60, 0), (8, "orthographic", 160, 225, -60, 10),
         (3, "equidistant", 150, 0, 89, 0), (21, "equisolid", 150, 0, -89, 0)]
DIST = dict(a=0.005, b=-0.01, c=0.004, d=6, e=-4, g=2, t=-1.5)


def make_project(d, src, gains=None):
    """The views as a project in d (views.pto), each view's samples times its gain."""
    lines = ['p f2 w1024 h512 v360 E0 R0 n"TIFF_m c:NONE r:CROP"\nm i5\n']
    for k, (f, lens, v, yaw, pitch, roll) in enumerate(VIEWS):
        spec = f"panotools:lens={lens},hfov={v}," + ",".join(f"{a}={b}" for a, b in DIST.items())
        view = pp.convert(src, "equirect", spec, yaw=yaw, pitch=pitch, roll=roll)
        if gains is not None:
            view = np.clip(view * gains[k], 0, 255).astype(np.uint8)
        pp.write(str(d / f"v{k}.png"), view, overwrite=True)
        dist = " ".join(f"{a}{b}" for a, b in DIST.items())
        lines.append(f"i w{view.shape[1]} h{view.shape[0]} f{f} v{v} r{roll} p{pitch} y{yaw} {dist} n\"v{k}.png\"\n")
    (d / "views.pto").write_text("".join(lines))
    return d / "views.pto"


def enblend(cli, d):
    subprocess.run([cli, "stitch", str(d / "views.pto"), str(d / "l_"), "--quiet", "--overwrite"], check=True)
    layers = sorted(str(p) for p in d.glob("l_*.tif"))
    subprocess.run(["enblend", "-f1024x512", "-o", str(d / "blend.tif"), *layers], check=True, capture_output=True)
    return pp.read(str(d / "blend.tif"))[..., :3]


def seams(cli, src, out):
    """Crops (rows 150-330, columns 180-420: the seams of views 0, 1 and 4) of enblend, feather,
    multiband and the truth, each 2x, side by side."""
    with tempfile.TemporaryDirectory() as tmp:
        d = pathlib.Path(tmp)
        project = make_project(d, src, gains=[0.8, 1.2, 0.9, 1.1, 1.15, 0.85, 1.0, 0.95])
        crops = [enblend(cli, d), pp.stitch_panorama(str(project))[..., :3],
                 pp.stitch_panorama(str(project), blend="multiband")[..., :3], src]
        crops = [np.repeat(np.repeat(c[150:330, 180:420], 2, 0), 2, 1) for c in crops]
        gap = np.full((crops[0].shape[0], 6, 3), 255, np.uint8)
        row = [crops[0]]
        for c in crops[1:]:
            row += [gap, c]
        pp.write(out, np.ascontiguousarray(np.concatenate(row, 1)), quality=90, overwrite=True)
    print(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cli", default=str(ROOT / "build/tools/panoproj"))
    ap.add_argument("--out", default=str(ROOT / "docs/gallery/stitch_enblend.jpg"))
    ap.add_argument("--seams", help="write the seams' picture here instead")
    args = ap.parse_args()
    src = pp.read(str(ROOT / "samples/images/jordan_pond_4096x2048.jpg"))[::4, ::4]
    if args.seams:
        return seams(args.cli, src, args.seams)
    with tempfile.TemporaryDirectory() as tmp:
        d = pathlib.Path(tmp)
        make_project(d, src)
        blend = enblend(args.cli, d)
        outline = np.zeros((512, 1024, 3), np.uint8)
        for layer in pp.stitch_layers(str(d / "views.pto")).layers:
            x, y = layer.offset
            a = layer.pixels[..., 3] > 0
            edge = a & ~(np.roll(a, 1, 0) & np.roll(a, -1, 0) & np.roll(a, 1, 1) & np.roll(a, -1, 1))
            h, w = a.shape
            outline[y:y + h, x:x + w][edge] = 255
        pp.write(args.out, np.ascontiguousarray(np.concatenate([blend, np.maximum(outline, src // 3)], 0)),
                 quality=88, overwrite=True)
    print(args.out)

if __name__ == "__main__":
    main()
