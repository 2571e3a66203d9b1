"""`panoproj undistort` against what SfM users run: pycolmap 4.2's undistort_images (pip) and
COLMAP 3.8's `colmap image_undistorter` (apt), on a COLMAP 3.x model of 8 OPENCV images (1920x1080
JPEG, strong barrel distortion, rendered here from the real Jordan Pond panorama through the
camera itself). Whole processes, interleaved, --runs times: medians with the spread (min-max),
and panoproj's time over each peer's per run. panoproj bilinear (COLMAP's kernel) and bicubic
(its default); all write JPEG.

    scripts/bench.sh undistort [--runs N]
"""
import argparse
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile

from bench_stitch import spread, timed

ROOT = pathlib.Path(__file__).resolve().parents[1]
BUILD = pathlib.Path(os.environ.get("PANOPROJ_BENCH_BUILD", ROOT / "build-bench"))
CLI = BUILD / "tools" / "panoproj"
PYTHON = ROOT / ".venv" / "bin" / "python"
SOURCE = ROOT / "samples" / "images" / "jordan_pond_4096x2048.jpg"
CAMERA = "1 OPENCV 1920 1080 1150 1152 960.4 539.6 -0.21 0.045 0.0007 -0.0004\n"


def model(work, n=8):
    (work / "sparse").mkdir()
    (work / "images").mkdir()
    (work / "sparse" / "cameras.txt").write_text(CAMERA)
    (work / "sparse" / "images.txt").write_text("".join(f"{k + 1} 1 0 0 0 {k} 0 0 1 img{k}.jpg\n\n" for k in range(n)))
    (work / "sparse" / "points3D.txt").write_text("")
    for k in range(n):
        subprocess.run([CLI, "convert", SOURCE, work / "images" / f"img{k}.jpg", "--to",
                        f"@{work / 'sparse' / 'cameras.txt'}#1", "--yaw", str(45 * k), "--quiet"], check=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=11)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        work = pathlib.Path(d)
        model(work)
        out = work / "out"

        def ours(interp):
            return [CLI, "undistort", work / "sparse", work / "images", out, "--interp", interp, "--overwrite", "-q"]

        runners = {"panoproj bilinear": ours("bilinear"), "panoproj bicubic": ours("bicubic"),
                   "pycolmap": [PYTHON, "-c", "import pycolmap, sys; pycolmap.undistort_images(*sys.argv[1:])",
                                out, work / "sparse", work / "images"]}
        if shutil.which("colmap"):
            runners["colmap 3.8"] = ["colmap", "image_undistorter", "--image_path", work / "images", "--input_path",
                                     work / "sparse", "--output_path", out]
        times = {k: [] for k in runners}
        for _ in range(args.runs):
            for name, cmd in runners.items():
                shutil.rmtree(out, ignore_errors=True)
                times[name].append(timed([str(c) for c in cmd]))
        for name, ts in times.items():
            line = f"{name:18s} {spread(ts)} s"
            if not name.startswith("panoproj"):
                for ours_name in ("panoproj bilinear", "panoproj bicubic"):
                    ratio = [a / b for a, b in zip(times[ours_name], ts)]
                    line += f"; {ours_name} / it {spread(ratio)}"
            print(line)
        print(f"({args.runs} interleaved runs, 8 images 1920x1080 JPEG, {os.cpu_count()} cores)", file=sys.stderr)


if __name__ == "__main__":
    main()
