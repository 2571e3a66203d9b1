"""GoPro MAX 5.6K pairs -> 5376x2688 equirect (issue 49's figures):

    scripts/bench.sh gopro-max [--runs N] [--max2sphere PATH] [--frames N]

- pairs: the real 5.6K pair (samples/gopro_max/), the whole process per pair, two JPEGs in and a
  JPEG out (quality 100, as max2sphere writes): panoproj against max2sphere if --max2sphere names
  its binary (built from trek-view/max2sphere outside this repository, for this benchmark only:
  `gcc -O3 -o max2sphere max2sphere.c bitmaplib.c -ljpeg -lm`; its lookup table made once
  beforehand, as its users run it), interleaved; frames a second and the ratio.
- convert: the conversion alone (panoproj.Plan on the pair's arrays, 2 threads), frames a second.
- video: a .360 made here (two HEVC streams of --frames frames from the pair, x265 ultrafast, an
  AAC stream) to an equirect MP4 (x264 ultrafast): the job's frames a second, its HEVC decode,
  convert and encode seconds apart.
Medians of --runs, with the spread (min-max).
"""
import argparse
import os
import pathlib
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
from PIL import Image

ROOT = pathlib.Path(__file__).resolve().parents[1]
BUILD = pathlib.Path(os.environ.get("PANOPROJ_BENCH_BUILD", ROOT / "build-bench"))  # (another Release build: this variable)
CLI = BUILD / "tools" / "panoproj"
FRAMES = ROOT / "samples" / "gopro_max"
PAIR = [FRAMES / "5_6k_track0_GS018421_1.jpg", FRAMES / "5_6k_track5_GS018421_1.jpg"]


def timed(cmd, **kw):
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, capture_output=True, **kw)
    return time.perf_counter() - t0


def spread(xs):
    return f"{statistics.median(xs):.3f} ({min(xs):.3f}-{max(xs):.3f})"


def pairs(runs, max2sphere, work):
    ours = [CLI, "convert", *PAIR, work / "ours.jpg", "--from", "gopro-max", "--to", "equirect", "--size", "5376x2688",
            "--quality", "100", "--overwrite"]
    peer = None
    if max2sphere:
        for t, f in zip((0, 5), PAIR):
            (work / f"track{t}").mkdir(exist_ok=True)
            shutil.copy(f, work / f"track{t}" / "f_1.jpg")
        peer = [os.path.abspath(max2sphere), "-w", "5376", "-n", "1", "-m", "1", "-o", str(work / "m2s_%d.jpg"),
                "track%d/f_%d.jpg"]
        timed(peer, cwd=work)  # (its lookup table, made once)
    t_ours, t_peer = [], []
    for _ in range(runs):
        t_ours.append(timed(ours))
        if peer:
            t_peer.append(timed(peer, cwd=work))
    print(f"pairs, whole process per pair (s): panoproj {spread(t_ours)}, {1 / statistics.median(t_ours):.2f} pairs/s")
    if peer:
        print(f"  max2sphere {spread(t_peer)}, {1 / statistics.median(t_peer):.2f} pairs/s; "
              f"panoproj's time {statistics.median(t_ours) / statistics.median(t_peer):.2f}x max2sphere's")


def convert_only(runs):
    sys.path.insert(0, str(BUILD / "python"))
    import panoproj
    strips = [np.asarray(Image.open(f)) for f in PAIR]
    both = np.concatenate(strips)
    plan = panoproj.Plan("gopro-max", "equirect", (both.shape[1], both.shape[0]), size=(5376, 2688), threads=2)
    out = plan(both)
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        plan.run(both, out=out)
        times.append(time.perf_counter() - t0)
    print(f"convert alone (Plan.run, kept maps): {spread(times)} s, {1 / statistics.median(times):.2f} frames/s")


def video(runs, frames, work):
    clips = []
    for t, f in zip((0, 5), PAIR):
        out = work / f"s{t}.mp4"
        subprocess.run(["ffmpeg", "-v", "error", "-y", "-loop", "1", "-framerate", "30", "-i", f, "-frames:v", str(frames),
                        "-vf", "scroll=h=0.0005", "-c:v", "libx265", "-preset", "ultrafast", "-x265-params",
                        "log-level=none", "-pix_fmt", "yuv420p", out], check=True)
        clips.append(out)
    clip = work / "clip.360"
    subprocess.run(["ffmpeg", "-v", "error", "-y", "-i", clips[0], "-f", "lavfi", "-i", f"sine=duration={frames / 30}",
                    "-i", clips[1], "-map", "0:0", "-map", "1:0", "-map", "2:0", "-c:v", "copy", "-c:a", "aac", "-f", "mp4",
                    clip], check=True)
    fps, dec, conv, enc = [], [], [], []
    for _ in range(runs):
        r = subprocess.run([CLI, "convert", clip, work / "out.mp4", "--to", "equirect", "--preset", "ultrafast",
                            "--overwrite"], check=True, capture_output=True, text=True)
        line = r.stdout.strip().splitlines()[-1]
        part = line[line.index("frames in"):]
        fps.append(float(part.split("(")[1].split(" fps")[0]))
        nums = part.split("decode ")[1]
        dec.append(float(nums.split(" s")[0]))
        conv.append(float(nums.split("convert ")[1].split(" s")[0]))
        enc.append(float(nums.split("encode ")[1].split(" s")[0]))
    print(f"video, .360 of {frames} frames -> 5376x2688 H.264 (ultrafast): {spread(fps)} fps; of it, seconds: "
          f"HEVC decode {spread(dec)}, convert {spread(conv)}, encode {spread(enc)}")
    print(f"  (decode alone {frames / statistics.median(dec):.1f} frames/s, convert alone "
          f"{frames / statistics.median(conv):.1f} frames/s, each on the threads the pipeline gives it)")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=11)
    ap.add_argument("--frames", type=int, default=30)
    ap.add_argument("--max2sphere", help="max2sphere's binary, built outside this repository")
    ap.add_argument("--only", default="pairs,convert,video")
    args = ap.parse_args()
    only = args.only.split(",")
    with tempfile.TemporaryDirectory() as tmp:
        work = pathlib.Path(tmp)
        if "pairs" in only:
            pairs(args.runs, args.max2sphere, work)
        if "convert" in only:
            convert_only(args.runs)
        if "video" in only:
            video(max(3, args.runs // 3), args.frames, work)


if __name__ == "__main__":
    main()
