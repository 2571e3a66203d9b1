"""Videos against FFmpeg's v360 (issue 47's figures):

    scripts/bench.sh video [--runs N] [--frames N] [--only filter,transcode,rss]

Clips (made once in build-bench/video/): the Jordan Pond equirect (4096x2048) turned a little a
frame, --frames frames (default 120) of H.264 4:2:0 at 30 fps (x264 crf 20 veryfast), and a dual
fisheye (200 degrees a lens, 4096x2048) made from it by panoproj.
- filter: decode + convert with no encoder: bench/video_throughput (the convert job's pipeline,
  its frames handed to a sink) against `ffmpeg -i clip -vf v360=...:interp=cubic -f null -`, for
  equirect -> cube 3x2 (3072x2048), EAC (3072x2048), a 90-degree 1920x1080 pinhole and the dual
  fisheye -> equirect (4096x2048); the cube, the pinhole and the dual fisheye again from the
  clips with their chroma marked left-sited (the clips themselves say centre). Frames a second
  and the ratio (target: 2x).
- transcode: the whole process with libx264 crf 20 at --preset medium and veryfast (cube 3x2):
  panoproj, v360 with cubic, and two floors: decode + the same encoder on frames of the output's
  size (`-vf crop=3072:2048`: the turning picture cropped, which x264 encodes faster than the
  cube's faces), and the same encoder on the cube's own frames (panoproj's, made once into raw
  YUV, read from the page cache: nothing but the encoder). The ratios to the floors (target: at
  most 1.25x) and to v360.
- rss: panoproj's peak RSS converting the clip of --frames and of 5x as many (flat in length).
Each subject runs --runs times, interleaved; figures are medians, with the spread (min-max).
"""
import argparse
import os
import pathlib
import shutil
import statistics
import subprocess
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
BUILD = ROOT / "build-bench"
CLI = BUILD / "tools" / "panoproj"
THROUGHPUT = BUILD / "bench" / "video_throughput"
DATA = BUILD / "video"
SOURCE = ROOT / "samples" / "images" / "jordan_pond_4096x2048.jpg"
PAUSE = 0.3


def timed(cmd):
    """Seconds and peak RSS (bytes) of a whole process."""
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(p.pid, 0)
    seconds = time.perf_counter() - t0
    err = p.stderr.read().decode(errors="replace")
    if os.waitstatus_to_exitcode(status) != 0:
        raise RuntimeError(f"{cmd} failed: {err}")
    return seconds, usage.ru_maxrss * 1024


def clip(frames):
    DATA.mkdir(parents=True, exist_ok=True)
    out = DATA / f"equirect_{frames}.mp4"
    if not out.exists():
        subprocess.run(["ffmpeg", "-v", "error", "-y", "-loop", "1", "-i", str(SOURCE), "-vf",
                        "scroll=horizontal=0.002,format=yuv420p", "-frames:v", str(frames), "-r", "30",
                        "-c:v", "libx264", "-crf", "20", "-preset", "veryfast", str(out)], check=True)
    return out


def left_clip(src):
    """Clip src re-encoded with its chroma marked left-sited (H.264's usual siting, and what an
    unmarked H.264 clip is taken for; the clips above say centre)."""
    out = src.with_name(f"left_{src.name}")
    if not out.exists():
        subprocess.run(["ffmpeg", "-v", "error", "-y", "-i", str(src), "-c:v", "libx264", "-crf", "20",
                        "-preset", "veryfast", "-chroma_sample_location", "left", str(out)], check=True)
    return out


def dual_clip(frames):
    out = DATA / f"dual_{frames}.mp4"
    if not out.exists():
        subprocess.run([str(CLI), "convert", str(clip(frames)), str(out), "--to", "dual-fisheye:fov=200",
                        "--size", "4096x2048", "--crf", "20", "--preset", "veryfast", "-q"], check=True)
    return out


def rounds(subjects, runs):
    """{name: [seconds]} over runs, the subjects interleaved."""
    times = {name: [] for name in subjects}
    for _ in range(runs):
        for name, cmd in subjects.items():
            time.sleep(PAUSE)
            times[name].append(timed(cmd)[0])
    return times


def median_spread(v):
    return statistics.median(v), min(v), max(v)


def filter_throughput(frames, runs, only):
    c, d = clip(frames), dual_clip(frames)
    pinhole = ("equirect", "pinhole:hfov=90", "1920x1080", "v360=e:flat:interp=cubic:w=1920:h=1080:h_fov=90:v_fov=58.7155")
    dual = ("dual-fisheye:fov=200", "equirect", "4096x2048",
            "v360=dfisheye:e:ih_fov=200:iv_fov=200:interp=cubic:w=4096:h=2048")
    cube = ("equirect", "cubemap:layout=3x2", "3072x2048", "v360=e:c3x2:interp=cubic:w=3072:h=2048")
    cases = [
        ("cube 3x2", c, *cube),
        ("EAC", c, "equirect", "cubemap:layout=eac", "3072x2048", "v360=e:eac:interp=cubic:w=3072:h=2048"),
        ("pinhole 90", c, *pinhole),
        ("dual fisheye -> equirect", d, *dual),
        ("cube 3x2, left-sited chroma", left_clip(c), *cube),
        ("pinhole 90, left-sited chroma", left_clip(c), *pinhole),
        ("dual fisheye, left-sited chroma", left_clip(d), *dual),
    ]
    print(f"\n== filter throughput: decode + convert, no encoder ({frames} frames, {runs} runs, fps median [min-max])")
    for name, src, frm, to, size, v360 in cases:
        if only and not any(o in name for o in only):
            continue
        subjects = {  # (--from always: a dual fisheye's 2:1 frame would be taken for an equirect)
            "panoproj": [str(THROUGHPUT), str(src), to, "--size", size, "--from", frm],
            "v360": ["ffmpeg", "-v", "error", "-i", str(src), "-vf", v360, "-f", "null", "-"],
        }
        t = rounds(subjects, runs)
        p, v = median_spread(t["panoproj"]), median_spread(t["v360"])
        fps = lambda s: frames / s
        print(f"{name:32s} panoproj {fps(p[0]):5.1f} fps [{fps(p[2]):.1f}-{fps(p[1]):.1f}]   "
              f"v360 {fps(v[0]):5.1f} fps [{fps(v[2]):.1f}-{fps(v[1]):.1f}]   ratio {v[0] / p[0]:.2f}x")


def cube_frames(frames):
    """The cube's frames as raw yuv420p (from a lossless FFV1 file): the second floor's input."""
    lossless, out = DATA / f"cube_{frames}.mkv", DATA / f"cube_{frames}.yuv"
    if not out.exists():
        subprocess.run([str(CLI), "convert", str(clip(frames)), str(lossless), "--to", "cubemap:layout=3x2", "--size",
                        "3072x2048", "--codec", "ffv1", "-q", "--overwrite"], check=True)
        subprocess.run(["ffmpeg", "-v", "error", "-y", "-i", str(lossless), "-f", "rawvideo", str(out)], check=True)
    return ["-f", "rawvideo", "-pix_fmt", "yuv420p", "-s", "3072x2048", "-r", "30", "-i", str(out)]


def transcode(frames, runs, presets):
    src = clip(frames)
    cube = cube_frames(frames)
    out = DATA / "out.mp4"
    print(f"\n== transcode to cube 3x2 3072x2048, libx264 crf 20 ({frames} frames, {runs} runs, seconds median [min-max])")
    for preset in presets:
        enc = ["-c:v", "libx264", "-crf", "20", "-preset", preset]
        subjects = {
            "panoproj": [str(CLI), "convert", str(src), str(out), "--to", "cubemap:layout=3x2", "--size", "3072x2048",
                         "--crf", "20", "--preset", preset, "--overwrite", "-q"],
            "v360": ["ffmpeg", "-v", "error", "-y", "-i", str(src), "-vf", "v360=e:c3x2:interp=cubic:w=3072:h=2048",
                     *enc, str(out)],
            "floor": ["ffmpeg", "-v", "error", "-y", "-i", str(src), "-vf", "crop=3072:2048", *enc, str(out)],
            "floor (cube frames)": ["ffmpeg", "-v", "error", "-y", *cube, *enc, str(out)],
        }
        t = rounds(subjects, runs)
        m = {k: median_spread(v) for k, v in t.items()}
        line = "   ".join(f"{k} {v[0]:.2f} s [{v[1]:.2f}-{v[2]:.2f}]" for k, v in m.items())
        print(f"{preset:9s} {line}\n          panoproj/floor {m['panoproj'][0] / m['floor'][0]:.2f}x   "
              f"panoproj/floor (cube frames) {m['panoproj'][0] / m['floor (cube frames)'][0]:.2f}x   "
              f"panoproj/v360 {m['panoproj'][0] / m['v360'][0]:.2f}x   "
              f"v360/floor (cube frames) {m['v360'][0] / m['floor (cube frames)'][0]:.2f}x")


def rss(frames):
    print("\n== peak RSS, cube 3x2, veryfast")
    out = DATA / "out.mp4"
    for n in (frames, 5 * frames):
        _, peak = timed([str(CLI), "convert", str(clip(n)), str(out), "--to", "cubemap:layout=3x2", "--size",
                         "3072x2048", "--preset", "veryfast", "--overwrite", "-q"])
        print(f"{n:5d} frames: {peak / 2**20:.0f} MB")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=11)
    ap.add_argument("--frames", type=int, default=120)
    ap.add_argument("--only", default="filter,transcode,rss")
    ap.add_argument("--presets", default="medium,veryfast")
    ap.add_argument("--cases", default="", help="filter cases whose names contain one of these (comma-separated)")
    a = ap.parse_args()
    if not shutil.which("ffmpeg"):
        raise SystemExit("bench_video: needs the ffmpeg command (apt install ffmpeg)")
    only = set(a.only.split(","))
    if "filter" in only:
        filter_throughput(a.frames, a.runs, [c for c in a.cases.split(",") if c])
    if "transcode" in only:
        transcode(a.frames, a.runs, a.presets.split(","))
    if "rss" in only:
        rss(a.frames)


if __name__ == "__main__":
    main()
