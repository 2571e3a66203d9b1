"""Converts a long 360 video on a Dask cluster: the clip cut by time into parts, one task a part,
then the parts joined into one file.

    python dask_convert_video.py IN OUT --to cubemap:layout=eac [--parts 8] [--workers 2]
        [--scheduler tcp://host:8786] [-- more panoproj convert options, e.g. --crf 20]

Each task runs `panoproj convert IN part_k --start S --duration D`: it decodes from the keyframe
before S and writes the frames whose time is in [S, S + D), their times counted from S, so each
frame is in exactly one part and converted as in the whole (panoproj's tests compare the two
bit for bit). The parts are joined with FFmpeg's concat demuxer and stream copy
(`ffmpeg -f concat -c copy`), which offsets each part's times by the parts before it: no frame
twice, none lost, no seam. The workers must see IN and OUT's folder at the same paths. Needs
the `panoproj` command (pip install panoproj) and FFmpeg's `ffprobe` and `ffmpeg` commands.
"""
import argparse
import json
import os
import pathlib
import shutil
import subprocess
import sysconfig
import tempfile


def panoproj_command():
    """The panoproj command: $PANOPROJ_CLI, else the one pip installed with this Python's
    panoproj (its environment's scripts, active or not), else the one on PATH."""
    beside = pathlib.Path(sysconfig.get_path("scripts")) / "panoproj"
    cli = os.environ.get("PANOPROJ_CLI") or (str(beside) if beside.is_file() else shutil.which("panoproj"))
    if not cli:
        raise FileNotFoundError("the panoproj command is not on PATH (pip install panoproj)")
    return cli


def duration_of(path):
    """The video stream's duration in seconds (ffprobe), else the container's."""
    out = subprocess.run(["ffprobe", "-v", "error", "-select_streams", "v:0", "-show_entries",
                          "stream=duration:format=duration", "-of", "json", str(path)],
                         check=True, capture_output=True, text=True).stdout
    info = json.loads(out)
    for d in [s.get("duration") for s in info.get("streams", [])] + [info.get("format", {}).get("duration")]:
        if d not in (None, "N/A"):
            return float(d)
    raise ValueError(f"{path}: ffprobe gives no duration")


def convert_part(src, out, start, duration, to, more):
    """One part: panoproj convert of the frames in [start, start + duration)."""
    cmd = [panoproj_command(), "convert", str(src), str(out), "--to", to, "--start", repr(start),
           "--threads", "1", "-q", "--overwrite", *more]
    if duration is not None:
        cmd += ["--duration", repr(duration)]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"part at {start} s failed: {r.stderr.strip()}")
    return str(out)


def join(parts, out):
    """The parts, in order, into out (stream copy), written beside it and renamed when whole."""
    out = pathlib.Path(out)
    listing = out.with_name(f".{out.name}.parts.txt")
    listing.write_text("".join(f"file '{pathlib.Path(p).resolve()}'\n" for p in parts))
    partial = out.with_name(f".{out.stem}.joining{out.suffix}")
    try:
        subprocess.run(["ffmpeg", "-v", "error", "-y", "-f", "concat", "-safe", "0", "-i", str(listing),
                        "-map", "0", "-c", "copy", str(partial)], check=True)
        os.replace(partial, out)
    finally:
        listing.unlink(missing_ok=True)
        partial.unlink(missing_ok=True)


def convert_video(client, src, out, to, parts=8, more=()):
    """Converts src into out in `parts` parts of equal time on the client; returns out."""
    total = duration_of(src)
    # Bounds in 1/1024 s: exact in binary, so each part's start + duration is the next's start
    # to the bit, and every frame's time falls in one part.
    bounds = [round(k * total / parts * 1024) / 1024 for k in range(parts)]
    out = pathlib.Path(out)
    with tempfile.TemporaryDirectory(dir=out.parent, prefix=f".{out.stem}.parts.") as work:
        futures = []
        for k in range(parts):
            # (The last part runs to the end: no frame is left past a rounded sum of durations.)
            start, duration = bounds[k], (None if k == parts - 1 else bounds[k + 1] - bounds[k])
            part = pathlib.Path(work) / f"part{k:04d}{out.suffix}"
            futures.append(client.submit(convert_part, str(src), str(part), start, duration, to, list(more),
                                         pure=False))
        join(client.gather(futures), out)
    return str(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("src")
    ap.add_argument("out")
    ap.add_argument("--to", required=True, help="target projection spec")
    ap.add_argument("--parts", type=int, default=8)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--scheduler", help="address of a running scheduler")
    ap.add_argument("more", nargs=argparse.REMAINDER, help="-- then more panoproj convert options")
    a = ap.parse_args()
    more = a.more[1:] if a.more[:1] == ["--"] else a.more
    from dask.distributed import Client, LocalCluster

    if a.scheduler:
        with Client(a.scheduler) as client:
            convert_video(client, a.src, a.out, a.to, a.parts, more)
    else:
        with LocalCluster(n_workers=a.workers, threads_per_worker=1) as cluster, Client(cluster) as client:
            convert_video(client, a.src, a.out, a.to, a.parts, more)
    print(f"{a.src} -> {a.out} in {a.parts} parts")


if __name__ == "__main__":
    main()
