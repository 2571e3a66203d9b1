#!/usr/bin/env python3
"""The picture of docs/stitching.md: eight views of the real Jordan Pond panorama (samples/images/)
through five lens types with a b c d e g t, written as a Hugin project, their layers made by
`panoproj stitch` and blended by enblend, beside the layers' outlines on the canvas.
Usage: stitch_figure.py [--cli PANOPROJ] [--out docs/gallery/stitch_enblend.jpg]   (needs enblend)"""
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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cli", default=str(ROOT / "build/tools/panoproj"))
    ap.add_argument("--out", default=str(ROOT / "docs/gallery/stitch_enblend.jpg"))
    args = ap.parse_args()
    src = pp.read(str(ROOT / "samples/images/jordan_pond_4096x2048.jpg"))[::4, ::4]
    with tempfile.TemporaryDirectory() as tmp:
        d = pathlib.Path(tmp)
        lines = ['p f2 w1024 h512 v360 E0 R0 n"TIFF_m c:NONE r:CROP"\nm i5\n']
        for k, (f, lens, v, yaw, pitch, roll) in enumerate(VIEWS):
            spec = f"panotools:lens={lens},hfov={v}," + ",".join(f"{a}={b}" for a, b in DIST.items())
            view = pp.convert(src, "equirect", spec, yaw=yaw, pitch=pitch, roll=roll)
            pp.write(str(d / f"v{k}.png"), view)
            dist = " ".join(f"{a}{b}" for a, b in DIST.items())
            lines.append(f"i w{view.shape[1]} h{view.shape[0]} f{f} v{v} r{roll} p{pitch} y{yaw} {dist} n\"v{k}.png\"\n")
        (d / "views.pto").write_text("".join(lines))
        subprocess.run([args.cli, "stitch", str(d / "views.pto"), str(d / "l_"), "--quiet"], check=True)
        layers = sorted(str(p) for p in d.glob("l_*.tif"))
        subprocess.run(["enblend", "-f1024x512", "-o", str(d / "blend.tif"), *layers], check=True, capture_output=True)
        blend = pp.read(str(d / "blend.tif"))[..., :3]
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
