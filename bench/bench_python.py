"""panoproj's Python module against py360convert (with opencv-python-headless: its cv2.remap path),
in one process, on the Jordan Pond equirect (4096x2048 uint8 RGB), bilinear, compute only.

    scripts/bench.sh python [--runs N] [--only keep]

- cold: nothing cached. py360convert's lru caches are cleared before each call; panoproj.convert
  builds its geometry each time (it keeps nothing).
- warm: the geometry cached. py360convert's caches kept; a panoproj.Plan after its first run.
- batch: 8 frames e2p (1920x1080) as one (8, H, W, 3) array in one convert call, against a
  Python loop of convert calls and a loop of py360convert.e2p: per-frame ms, interleaved rounds.
- two threads: 8 warm conversions, split over two Python threads at once, each library limited
  to one core (panoproj threads=1; cv2.setNumThreads(1)), against the 8 on one thread. The
  speed-up shows whether the GIL is released while converting.
- keep: panoproj.convert 20 times in a fresh process, keeping every output (a list, as
  `outs = [pp.convert(f, ...) for f in frames]` does: each call's output is new memory) against
  freeing each (the next call reuses its memory): per-call median, the ratio per round, e->cube
  6x1024 and e->pinhole 1920x1080 (target: keeping within 1.3x of freeing).
Each library uses its defaults otherwise (panoproj: every core; OpenCV: its own pool).
"""
import argparse
import functools
import inspect
import pathlib
import statistics
import sys
import threading
import time

import cv2
import numpy as np
import py360convert
import py360convert.utils

import panoproj as pp
from panoproj import compat

ROOT = pathlib.Path(__file__).resolve().parents[1]
FACE = 1024
HFOV, OUT_W, OUT_H = 90.0, 1920, 1080
VFOV = float(np.degrees(2 * np.arctan(np.tan(np.radians(HFOV / 2)) * OUT_H / OUT_W)))


def clear_py360_caches():
    """Every functools.lru_cache in py360convert.utils (functions and classmethods)."""
    for obj in vars(py360convert.utils).values():
        if hasattr(obj, "cache_clear"):
            obj.cache_clear()
        if inspect.isclass(obj):
            for attr in vars(obj).values():
                f = getattr(attr, "__func__", attr)
                if hasattr(f, "cache_clear"):
                    f.cache_clear()


def median_ms(fn, runs, before=None):
    times = []
    for _ in range(runs):
        if before:
            before()
        t = time.perf_counter()
        fn()
        times.append((time.perf_counter() - t) * 1e3)
    return statistics.median(times)


def two_threads_speedup(fn, n=8):
    """Time of n calls on one thread over the time of n calls split across two threads."""
    t = time.perf_counter()
    for _ in range(n):
        fn()
    one = time.perf_counter() - t
    threads = [threading.Thread(target=lambda: [fn() for _ in range(n // 2)]) for _ in range(2)]
    t = time.perf_counter()
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    return one / (time.perf_counter() - t)


def compat_table(e, cube, runs):
    """panoproj.compat against py360convert, the same calls: first calls (both caches cleared
    before each) and repeat calls (both kept), interleaved, medians of `runs`."""
    h, w = e.shape[:2]
    calls = {
        "e2c": lambda m: m.e2c(e, face_w=FACE, mode="bilinear", cube_format="horizon"),
        "c2e": lambda m: m.c2e(cube, h, w, mode="bilinear", cube_format="horizon"),
        "e2p": lambda m: m.e2p(e, (HFOV, VFOV), 0, 0, (OUT_H, OUT_W), mode="bilinear"),
    }
    print(f"panoproj.compat vs py360convert, 4096x2048 uint8 RGB (faces of {FACE}), bilinear, "
          f"median of {runs}, interleaved")
    print()
    print("| call | py360convert first ms | compat first ms | first speed-up | "
          "py360convert repeat ms | compat repeat ms | repeat speed-up |")
    print("|---|---|---|---|---|---|---|")
    for name, call in calls.items():
        times = {k: [] for k in ("their_first", "our_first", "their_repeat", "our_repeat")}
        for _ in range(runs):
            for who, module, clear in (("their", py360convert, clear_py360_caches), ("our", compat, compat.clear_cache)):
                clear()
                t0 = time.perf_counter()
                call(module)
                times[f"{who}_first"].append(time.perf_counter() - t0)
                t0 = time.perf_counter()
                call(module)
                times[f"{who}_repeat"].append(time.perf_counter() - t0)
        m = {k: 1000 * statistics.median(v) for k, v in times.items()}
        print(f"| {name} | {m['their_first']:.1f} | {m['our_first']:.1f} | {m['their_first'] / m['our_first']:.1f}x | "
              f"{m['their_repeat']:.1f} | {m['our_repeat']:.1f} | {m['their_repeat'] / m['our_repeat']:.1f}x |")


def batch_table(e, runs):
    """Per-frame ms of 8 frames e2p: a batch call, a Python loop, py360convert's loop (interleaved)."""
    frames = np.stack([np.roll(e, 512 * i, axis=1) for i in range(8)])
    spec, size = f"pinhole:hfov={HFOV}", (OUT_W, OUT_H)
    ways = {
        "panoproj batch (one call)": lambda: pp.convert(frames, "equirect", spec, size=size, interp="bilinear"),
        "panoproj Python loop": lambda: [pp.convert(f, "equirect", spec, size=size, interp="bilinear") for f in frames],
        "py360convert loop": lambda: [py360convert.e2p(f, (HFOV, VFOV), 0, 0, (OUT_H, OUT_W), mode="bilinear")
                                      for f in frames],
    }
    times = {k: [] for k in ways}
    for _ in range(runs):
        for name, fn in ways.items():
            time.sleep(0.2)  # let the other library's pool settle
            t = time.perf_counter()
            fn()
            times[name].append((time.perf_counter() - t) * 1000 / len(frames))
    print("| 8 frames e2p 1920x1080 | per-frame ms (median) | spread (min-max) |")
    print("|---|---|---|")
    for name, t in times.items():
        print(f"| {name} | {statistics.median(t):.1f} | {min(t):.1f}-{max(t):.1f} |")


KEEP_PAIRS = {"e->cube": ("cubemap", (6 * FACE, FACE)), "e->pinhole": (f"pinhole:hfov={HFOV}", (OUT_W, OUT_H))}


def keep_child(pair, keep):
    """(In a fresh process) per-call ms of 20 converts of turned frames, kept or freed."""
    e = pp.read(str(ROOT / "samples/images/jordan_pond_4096x2048.jpg"))
    frames = [np.roll(e, 200 * i, axis=1) for i in range(4)]
    spec, size = KEEP_PAIRS[pair]
    kept, times = [], []
    for i in range(20):
        t = time.perf_counter()
        out = pp.convert(frames[i % 4], "equirect", spec, size=size, interp="bilinear")
        times.append((time.perf_counter() - t) * 1e3)
        if keep:
            kept.append(out)
        del out
    print(statistics.median(times))


def keep_table(rounds):
    import subprocess
    print("| 20 converts, one process | keeping ms/call | freeing ms/call | keeping / freeing |")
    print("|---|---|---|---|")
    for pair in KEEP_PAIRS:
        ms = {True: [], False: []}
        ratios = []
        for _ in range(rounds):
            for keep in (True, False):
                time.sleep(0.3)
                r = subprocess.run([sys.executable, __file__, "--keep-child", pair] + (["--kept"] if keep else []),
                                   check=True, capture_output=True, text=True)
                ms[keep].append(float(r.stdout.split()[-1]))
            ratios.append(ms[True][-1] / ms[False][-1])
        fmt = lambda v: f"{statistics.median(v):.1f} ({min(v):.1f}-{max(v):.1f})"
        print(f"| {pair} | {fmt(ms[True])} | {fmt(ms[False])} | {statistics.median(ratios):.2f} "
              f"({min(ratios):.2f}-{max(ratios):.2f}) |")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--only", choices=["all", "keep", "compat"], default="all")
    ap.add_argument("--keep-child", help=argparse.SUPPRESS)
    ap.add_argument("--kept", action="store_true", help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.keep_child:
        return keep_child(a.keep_child, a.kept)
    if a.only == "compat":
        e = pp.read(str(ROOT / "samples/images/jordan_pond_4096x2048.jpg"))
        return compat_table(e, pp.convert(e, "equirect", "cubemap", size=(6 * FACE, FACE), interp="bilinear"),
                            max(a.runs, 11))
    keep_table(max(a.runs, 5))
    if a.only == "keep":
        return
    print()
    e = pp.read(str(ROOT / "samples/images/jordan_pond_4096x2048.jpg"))
    h, w = e.shape[:2]
    cube = pp.convert(e, "equirect", "cubemap", size=(6 * FACE, FACE), interp="bilinear")
    assert np.array_equal(np.concatenate(pp.split_faces(cube), axis=1), cube)

    plans = {
        "e2c": (pp.Plan("equirect", "cubemap", (w, h), size=(6 * FACE, FACE), interp="bilinear"), e),
        "c2e": (pp.Plan("cubemap", "equirect", (6 * FACE, FACE), size=(w, h), interp="bilinear"), cube),
        "e2p": (pp.Plan("equirect", f"pinhole:hfov={HFOV}", (w, h), size=(OUT_W, OUT_H), interp="bilinear"), e),
    }
    ours_cold = {
        "e2c": lambda: pp.convert(e, "equirect", "cubemap", size=(6 * FACE, FACE), interp="bilinear"),
        "c2e": lambda: pp.convert(cube, "cubemap", "equirect", size=(w, h), interp="bilinear"),
        "e2p": lambda: pp.convert(e, "equirect", f"pinhole:hfov={HFOV}", size=(OUT_W, OUT_H), interp="bilinear"),
    }
    theirs = {
        "e2c": lambda: py360convert.e2c(e, face_w=FACE, mode="bilinear", cube_format="horizon"),
        "c2e": lambda: py360convert.c2e(cube, h, w, mode="bilinear", cube_format="horizon"),
        "e2p": lambda: py360convert.e2p(e, (HFOV, VFOV), 0, 0, (OUT_H, OUT_W), mode="bilinear"),
    }
    print(f"panoproj {pp.simd_target()} vs py360convert {py360convert.__version__} "
          f"(OpenCV {cv2.__version__}), 4096x2048 uint8 RGB, bilinear, median of {a.runs}")
    print()
    print("| conversion | py360convert cold ms | panoproj cold ms | cold speed-up | "
          "py360convert warm ms | panoproj warm ms | warm speed-up |")
    print("|---|---|---|---|---|---|---|")
    for name in ("e2c", "c2e", "e2p"):
        plan, src = plans[name]
        plan(src)  # its map, if any, is built once
        their_cold = median_ms(theirs[name], a.runs, before=clear_py360_caches)
        our_cold = median_ms(ours_cold[name], a.runs)
        theirs[name]()
        their_warm = median_ms(theirs[name], a.runs)
        our_warm = median_ms(functools.partial(plan, src), a.runs)
        print(f"| {name} | {their_cold:.1f} | {our_cold:.1f} | {their_cold / our_cold:.1f}x | "
              f"{their_warm:.1f} | {our_warm:.1f} | {their_warm / our_warm:.1f}x |")
    print()
    compat_table(e, cube, max(a.runs, 11))
    print()
    batch_table(e, a.runs)
    print()
    cv2.setNumThreads(1)
    one_core = pp.Plan("equirect", "cubemap", (w, h), size=(6 * FACE, FACE), interp="bilinear", threads=1)
    one_core(e)
    buffers = threading.local()  # one output buffer per thread, as a video loop would keep

    def into_buffer():
        if not hasattr(buffers, "out"):
            buffers.out = one_core(e)
        one_core.run(e, out=buffers.out)

    ours = [two_threads_speedup(functools.partial(one_core, e)) for _ in range(3)]
    ours_kept = [two_threads_speedup(into_buffer) for _ in range(3)]
    py = [two_threads_speedup(theirs["e2c"]) for _ in range(3)]
    print(f"two Python threads at once, one core each (e2c, 8 conversions, median of 3): the "
          f"one-thread throughput x {statistics.median(ours):.2f} for panoproj (new output arrays), "
          f"x {statistics.median(ours_kept):.2f} (outputs written into kept arrays), "
          f"x {statistics.median(py):.2f} for py360convert")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
