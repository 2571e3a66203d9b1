"""Where the bilinear time goes: bench_remap's bilinear conversions (panoproj only, one thread)
under `perf record`, the samples grouped by engine phase, as shares of the conversion's samples.

    scripts/bench.sh profile [--runs N]

The bench's set-up (decoding the JPEG, making its cube and dual-fisheye sources with bicubic) is
left out of the shares: libjpeg's samples and the bicubic/Lanczos gathers (K 4 or 6).
"""
import argparse
import pathlib
import re
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[1]
CASES = {0: "e->cube", 3: "e->fisheye", 5: "e->pinhole", 6: "cube->e"}  # bench_remap's bilinear rows
PHASES = [  # (name, pattern on "dso symbol"); the first match counts
    ("set-up (left out)", r"libjpeg|GatherBlocks<[^>]*, [46]>"),
    ("gathers and blends (phase 2)", r"GatherBlocks"),
    ("fused geometry and tap planning: positions, floors, bounds, offsets, prefetches (phase 1)", r"PlanFusedRows|PlanMapRows|PlanLanes"),
    ("geometry: grid nodes, exact checks, per-tile tables", r"BuildGrid|TileRows"),
    ("geometry: tile maps of non-fused tiles", r"TileMap|tile_map"),
    ("kernel: page faults, zeroing (the set-up's too), scheduling", r"\[kernel"),
]
LINE = re.compile(r"^\s*([\d.]+)%\s+(\S+)\s+\[[.k]\]\s+(.*)$")


def profile(build, case, runs):
    with tempfile.NamedTemporaryFile(suffix=".data") as data:
        subprocess.run(["perf", "record", "-q", "-o", data.name, "--", f"{build}/bench/bench_remap", "--ours-only",
                        "--threads", "1", "--runs", str(runs), "--case", str(case)],
                       check=True, capture_output=True)
        report = subprocess.run(["perf", "report", "-i", data.name, "--stdio", "--no-children", "--sort", "dso,symbol"],
                                check=True, capture_output=True, text=True).stdout
    shares = {name: 0.0 for name, _ in PHASES}
    shares["other"] = 0.0
    for line in report.splitlines():
        m = LINE.match(line)
        if not m:
            continue
        pct, what = float(m.group(1)), f"{m.group(2)} {m.group(3)}"
        phase = next((name for name, pat in PHASES if re.search(pat, what)), "other")
        shares[phase] += pct
    setup = shares.pop(PHASES[0][0])
    total = sum(shares.values())
    return {k: 100 * v / total for k, v in shares.items()}, setup


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=40)
    ap.add_argument("--build", default=str(ROOT / "build-bench"))
    a = ap.parse_args()
    results = {name: profile(a.build, case, a.runs) for case, name in CASES.items()}
    names = list(next(iter(results.values()))[0])
    print("| phase (% of the conversion's samples, one thread) | " + " | ".join(results) + " |")
    print("|---" * (len(results) + 1) + "|")
    for n in names:
        print(f"| {n} | " + " | ".join(f"{r[0][n]:.0f}" for r in results.values()) + " |")
    print(f"\n(set-up samples left out: " + ", ".join(f"{k} {r[1]:.0f}%" for k, r in results.items()) + ")")


if __name__ == "__main__":
    sys.exit(main())
