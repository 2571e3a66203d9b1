"""panoproj against cv2.remap of the OpenCV line this interpreter has (pip's opencv-python-headless,
pinned by scripts/bench.sh cv: 4.14.0.94 and 5.0.0.93, each in its own environment), in one
process: uint8 RGB, 2 threads, antialias off, cv2's maps built beforehand (free), compute only.

    scripts/bench.sh cv [--runs N] [--rounds N]

Per pair and kernel, interleaved: cv2.remap with the maps, panoproj.convert (its map built
inside), and Plan.run(out=) (a warm plan, a preallocated output); a pause between libraries
(their thread pools spin). Each round's median of --runs calls; the rounds' median and range.
panoproj's lanczos3 (6x6 taps) is set against cv2's INTER_LANCZOS4 (8x8), its nearest kernel.
--json writes the rows; --combine A.json B.json prints the faster line per pair and kernel.
"""
import argparse
import json
import pathlib
import statistics
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
PAIRS = [  # name, source spec, target spec, target size (w, h)
    ("e->cube", "equirect", "cubemap", (6144, 1024)),
    ("e->fisheye", "equirect", "fisheye:fov=180", (1536, 1536)),
    ("e->pinhole", "equirect", "pinhole:hfov=90", (1920, 1080)),
    ("cube->e", "cubemap", "equirect", (4096, 2048)),
]
KERNELS = [("bilinear", "INTER_LINEAR"), ("bicubic", "INTER_CUBIC"), ("lanczos3", "INTER_LANCZOS4")]


def median_ms(fn, runs):
    times = []
    for _ in range(runs):
        t = time.perf_counter()
        fn()
        times.append((time.perf_counter() - t) * 1e3)
    return statistics.median(times)


def measure(runs, rounds, pause):
    import cv2
    import panoproj as pp

    cv2.setNumThreads(2)
    pano = pp.read(str(ROOT / "samples/images/jordan_pond_4096x2048.jpg"))
    sources = {"equirect": pano, "cubemap": pp.convert(pano, "equirect", "cubemap", size=(6144, 1024))}
    rows = []
    for name, src, dst, size in PAIRS:
        image = sources[src]
        source_size = (image.shape[1], image.shape[0])
        mx, my = pp.build_map(src, dst, source_size, size=size)
        for kernel, cv_kernel in KERNELS:
            flag = getattr(cv2, cv_kernel)
            kw = dict(size=size, interp=kernel, antialias="off", threads=2)
            plan = pp.Plan(src, dst, source_size, **kw)
            out = np.empty((size[1], size[0], 3), np.uint8)
            plan.run(image, out=out)
            subjects = {
                "cv2": lambda: cv2.remap(image, mx, my, flag, borderMode=cv2.BORDER_CONSTANT),
                "convert": lambda: pp.convert(image, src, dst, **kw),
                "plan": lambda: plan.run(image, out=out),
            }
            for f in subjects.values():  # warm-up: pools started, pages touched
                f()
            per_round = {k: [] for k in subjects}
            for _ in range(rounds):
                for k, f in subjects.items():
                    time.sleep(pause)
                    per_round[k].append(median_ms(f, runs))
            row = {"pair": name, "kernel": kernel, "cv2_version": cv2.__version__}
            for k, v in per_round.items():
                row[k] = {"median": statistics.median(v), "min": min(v), "max": max(v)}
            rows.append(row)
            print_row(row)
    return rows


def print_row(row):
    c, v, p = row["cv2"], row["convert"], row["plan"]
    print(f"| {row['pair']} | {row['kernel']} | {row['cv2_version']} | {c['median']:.2f} ({c['min']:.2f}-{c['max']:.2f}) "
          f"| {v['median']:.2f} ({v['min']:.2f}-{v['max']:.2f}) | {p['median']:.2f} ({p['min']:.2f}-{p['max']:.2f}) "
          f"| {v['median'] / c['median']:.2f} | {p['median'] / c['median']:.2f} |", flush=True)


HEADER = ("| pair | kernel | cv2 | cv2.remap ms | convert ms | Plan.run ms | convert / cv2 | Plan / cv2 |\n"
          "|---|---|---|---|---|---|---|---|")


def combine(paths):
    """Per pair and kernel, the row of the faster cv2 line (its median)."""
    best = {}
    for path in paths:
        for row in json.loads(pathlib.Path(path).read_text()):
            key = (row["pair"], row["kernel"])
            if key not in best or row["cv2"]["median"] < best[key]["cv2"]["median"]:
                best[key] = row
    print("Against the faster OpenCV line per pair and kernel:\n" + HEADER)
    for row in best.values():
        print_row(row)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=11)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--pause", type=float, default=0.5)
    ap.add_argument("--json")
    ap.add_argument("--combine", nargs="+")
    a = ap.parse_args()
    if a.combine:
        return combine(a.combine)
    print(HEADER)
    rows = measure(a.runs, a.rounds, a.pause)
    if a.json:
        pathlib.Path(a.json).write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    sys.exit(main())
