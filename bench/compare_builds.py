"""Two builds of panoproj against each other (e.g. before and after a restructuring): bench_remap
(panoproj's rows only) and the Python bench, run in turns (old, new, old, new ...) with pauses, so
that the shared machine's load hits both alike. Prints, per case, the median over rounds of each
build's per-run median, the spread (min..max over rounds) and new / old.

    .venv/bin/python bench/compare_builds.py OLD_BUILD NEW_BUILD [--rounds 5] [--runs 11] [--only remap|python]

Each BUILD is a directory made by scripts/bench.sh (build-bench/: bench/bench_remap, python/).
"""
import argparse
import os
import pathlib
import statistics
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]


def table_rows(text):
    """The cells of each markdown table row that is not a header or rule."""
    for line in text.splitlines():
        if line.startswith("| ") and not line.startswith("|---") and "ms |" not in line:
            yield [c.strip() for c in line.strip("|").split("|")]


def remap_cases(build, runs):
    out = subprocess.run([f"{build}/bench/bench_remap", "--ours-only", "--runs", str(runs)], check=True,
                         capture_output=True, text=True).stdout
    return {f"remap: {r[0].split(' (')[0]}, {r[1]}": float(r[2]) for r in table_rows(out)}


def python_cases(build, runs):
    env = dict(os.environ, PYTHONPATH=f"{build}/python")
    out = subprocess.run([sys.executable, str(ROOT / "bench/bench_python.py"), "--runs", str(runs)], check=True,
                         capture_output=True, text=True, env=env).stdout
    cases = {}
    for r in table_rows(out):
        cases[f"python: {r[0]} cold"] = float(r[2])
        cases[f"python: {r[0]} warm"] = float(r[5])
    return cases


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--runs", type=int, default=11)
    ap.add_argument("--pause", type=float, default=2.0, help="seconds between runs (thread pools spin down)")
    ap.add_argument("--only", choices=("remap", "python"), help="one of the two benchmarks")
    a = ap.parse_args()
    times = {"old": {}, "new": {}}
    for i in range(a.rounds):
        for which, build in (("old", a.old), ("new", a.new)) if i % 2 == 0 else (("new", a.new), ("old", a.old)):
            for bench in [b for n, b in (("remap", remap_cases), ("python", python_cases)) if a.only in (None, n)]:
                for case, ms in bench(build, a.runs).items():
                    times[which].setdefault(case, []).append(ms)
                time.sleep(a.pause)
        print(f"round {i + 1} of {a.rounds} done", file=sys.stderr)
    print(f"{a.rounds} rounds in turns, each the median of {a.runs} runs; ms: median over rounds (min..max)\n")
    print("| case | old ms | new ms | new / old |")
    print("|---|---|---|---|")
    ratios = []
    for case in times["old"]:
        o, n = times["old"][case], times["new"][case]
        ratio = statistics.median(n) / statistics.median(o)
        ratios.append(ratio)
        print(f"| {case} | {statistics.median(o):.1f} ({min(o):.1f}..{max(o):.1f}) | "
              f"{statistics.median(n):.1f} ({min(n):.1f}..{max(n):.1f}) | {ratio:.3f} |")
    print(f"\nnew / old over the {len(ratios)} cases: median {statistics.median(ratios):.3f}, "
          f"range {min(ratios):.3f}..{max(ratios):.3f}")


if __name__ == "__main__":
    main()
