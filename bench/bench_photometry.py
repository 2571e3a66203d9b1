"""The photometric keys' cost in convert (issue 51's figure): a 360 camera's dual-fisheye frame
(5760x2880 JPEG, made here from the real Jordan Pond panorama) to a 5760x2880 equirect JPEG, and
one 2880x2880 fisheye to a 2000x2000 pinhole view, each with every key non-trivial (EMoR response,
per-lens exposures, white balance, vignetting with a shifted centre) against the same conversion
without them. Whole processes, interleaved, --runs times: medians with the spread (min-max), and
the ratio per run.

    scripts/bench.sh photometry [--runs N]
"""
import argparse
import os
import pathlib
import subprocess
import tempfile

from bench_stitch import spread, timed

ROOT = pathlib.Path(__file__).resolve().parents[1]
BUILD = pathlib.Path(os.environ.get("PANOPROJ_BENCH_BUILD", ROOT / "build-bench"))
CLI = BUILD / "tools" / "panoproj"
SOURCE = ROOT / "samples" / "images" / "jordan_pond_4096x2048.jpg"
KEYS = "response=0.5/-0.3/0.2/0.1/-0.05,wb=1.1/0.9,vignetting=1/-0.3/0.1/-0.05,vignetting_centre=20/-10"
CASES = {
    "dual-fisheye": ("dual.jpg", "dual-fisheye:fov=200", f",{KEYS},ev=0.3,ev2=-0.4", "equirect", "5760x2880"),
    "fisheye": ("lens.jpg", "fisheye:fov=190", f",{KEYS},ev=0.7", "pinhole:hfov=100", "2000x2000"),
}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=11)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        work = pathlib.Path(d)
        subprocess.run([CLI, "convert", SOURCE, work / "dual.jpg", "--to", "dual-fisheye:fov=200", "--size",
                        "5760x2880", "--quiet"], check=True)
        subprocess.run([CLI, "convert", SOURCE, work / "lens.jpg", "--to", "fisheye:fov=190", "--size", "2880x2880",
                        "--quiet"], check=True)
        for name, (src, spec, keys, to, size) in CASES.items():
            plain, corrected = [], []
            for _ in range(args.runs):
                for spec_of, times in ((spec, plain), (spec + keys, corrected)):
                    target = to + ((":" if ":" not in to else ",") + "ev=0" if spec_of != spec else "")
                    times.append(timed([CLI, "convert", work / src, work / "out.jpg", "--from", spec_of, "--to", target,
                                        "--size", size, "--overwrite", "--quiet"]))
            ratios = [c / p for c, p in zip(corrected, plain)]
            print(f"{name:13s} plain {spread(plain)} s, with the keys {spread(corrected)} s, "
                  f"ratio {spread(ratios)} ({args.runs} interleaved runs)")


if __name__ == "__main__":
    main()
