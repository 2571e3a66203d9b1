"""The tile pyramids' heavy oracles (scripts/tiles-oracle.sh runs them; not in CI).

    tiles_oracle.py generate-py WORK GENERATE_PY PYTHON   Pannellum's generate.py (nona + Pillow)
    tiles_oracle.py browser WORK BASE_URL                 Pannellum and Marzipano in Chromium
    tiles_oracle.py big WORK GENERATE_PY PYTHON           32768x16384: time and peak memory

generate-py: the same panorama through generate.py --png and `panoproj tiles --format png`:
the same file names, and per level and face the PSNR of our face (its tiles joined) against each
of generate.py's six, so a face letter or turn that disagrees shows as a better match elsewhere.

browser: pyramids of both viewers opened by their own scripts at set views (tiles_viewers.mjs),
each screenshot against panoproj's pinhole render of the same view from the level the viewer
shows (the source to a cube at that level's size, then bilinear to the view, as the GPU samples
it). A pyramid whose up face is turned a quarter must fail the views that see it.
"""
import json
import os
import pathlib
import resource
import shutil
import subprocess
import sys
import time

import numpy as np

import panoproj as pp

ROOT = pathlib.Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples/images/jordan_pond_4096x2048.jpg"
CLI = os.environ.get("PANOPROJ_CLI", str(ROOT / "build/tools/panoproj"))
LETTERS = "frblud"


def psnr(a, b):
    d = a[..., :3].astype(np.float64) - b[..., :3].astype(np.float64)
    mse = float(np.mean(d * d))
    return 99.0 if mse == 0 else 10 * np.log10(255.0 ** 2 / mse)


def pannellum_face(folder, level, letter, size, tile, ext="png"):
    rows = []
    for r in range(-(-size // tile)):
        rows.append(np.concatenate([pp.read(str(folder / str(level) / f"{letter}{r}_{c}.{ext}"))[..., :3]
                                    for c in range(-(-size // tile))], axis=1))
    return np.concatenate(rows, axis=0)


def run_timed(cmd, **kw):
    """Runs cmd; returns (seconds, peak RSS of the children in MB)."""
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, **kw)
    return time.perf_counter() - t0, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024


def generate_py(work, script, python):
    work = pathlib.Path(work).resolve()
    ours, theirs = work / "ours", work / "generate_py"
    for d in (ours, theirs):
        shutil.rmtree(d, ignore_errors=True)
    subprocess.run([python, script, str(SAMPLE), "--png", "-o", str(theirs)], check=True, stdout=subprocess.DEVNULL)
    subprocess.run([CLI, "tiles", str(SAMPLE), str(ours), "--format", "png", "-q"], check=True)
    cfg_t, cfg_o = json.loads((theirs / "config.json").read_text()), json.loads((ours / "config.json").read_text())
    keys = ("cubeResolution", "tileResolution", "maxLevel", "path", "extension", "fallbackPath")
    same_config = all(cfg_t["multiRes"][k] == cfg_o["multiRes"][k] for k in keys)
    names = lambda d: sorted(str(p.relative_to(d)) for p in d.rglob("*.png"))  # noqa: E731
    same_names = names(ours) == names(theirs)
    print(f"config.json multiRes {', '.join(keys)}: {'equal' if same_config else 'DIFFERENT'} "
          f"({json.dumps(cfg_o['multiRes'])})")
    print(f"file names: {'equal' if same_names else 'DIFFERENT'} ({len(names(ours))} files)")
    m = cfg_o["multiRes"]
    ok = same_config and same_names
    print("\nlevel  size  face: dB against generate.py's same face (best other face)")
    for level in range(1, m["maxLevel"] + 1):
        size = m["cubeResolution"] >> (m["maxLevel"] - level)
        faces_o = {f: pannellum_face(ours, level, f, size, m["tileResolution"]) for f in LETTERS}
        faces_t = {f: pannellum_face(theirs, level, f, size, m["tileResolution"]) for f in LETTERS}
        cells = []
        for f in LETTERS:
            same = psnr(faces_o[f], faces_t[f])
            # Every other face, and this face turned a quarter, half and three quarters.
            others = [psnr(faces_o[f], faces_t[g]) for g in LETTERS if g != f]
            turned = [psnr(np.rot90(faces_o[f], k), faces_t[f]) for k in (1, 2, 3)]
            best_other = max(others + turned)
            cells.append(f"{f} {same:5.2f} ({best_other:5.2f})")
            ok = ok and same > best_other + 6 and (level != m["maxLevel"] or same >= 35)
        print(f"{level:5d} {size:5d}  " + "  ".join(cells))
    print("\ngenerate.py oracle:", "PASS" if ok else "FAIL")
    return ok


# Views off the cube's axes by a fraction of a degree: both viewers, in SwiftShader, drop quads
# with a corner exactly on the camera's plane (yaw 0 pitch 0 hfov 100 leaves Marzipano's side faces
# white, yaw 45 pitch 0 hfov 100 puts a wedge of wrong texture into Pannellum's view, with
# generate.py's pyramid as with ours). Fields of view of 80 degrees and more: Marzipano's limiter
# (traditional(faceSize)) widens a view that would magnify its top level past 1:1.
VIEWS = [(0.7, 0.4, 90), (130, 15, 80), (-60, 75, 90), (200, -70, 90), (45.3, 0.6, 100), (-100, -10, 110)]


def viewer_level(viewer, config, hfov, width=800, height=600):
    """The level the viewer shows (its own rule) and that level's face size."""
    if viewer == "pannellum":
        m = config["multiRes"]
        level = 1
        while level < m["maxLevel"] and width > m["tileResolution"] * 2 ** (level - 1) * np.tan(np.radians(hfov) / 2) * 0.707:
            level += 1
        return level, int(m["cubeResolution"] // 2 ** (m["maxLevel"] - level))
    vfov = 2 * np.arctan(np.tan(np.radians(hfov) / 2) * height / width)
    levels = [l for l in config["levels"] if not l.get("fallbackOnly")]
    for i, l in enumerate(levels):
        if np.tan(vfov / 2) * l["size"] >= height:
            return i + 1, l["size"]
    return len(levels), levels[-1]["size"]


def turn_up_face(folder, config):
    """The deliberate mistake: every level's up face turned a quarter (Pannellum's layout)."""
    m = config["multiRes"]
    for level in range(1, m["maxLevel"] + 1):
        size = m["cubeResolution"] >> (m["maxLevel"] - level)
        t = m["tileResolution"]
        face = np.rot90(pannellum_face(folder, level, "u", size, t, m["extension"]))
        for r in range(-(-size // t)):
            for c in range(-(-size // t)):
                pp.write(str(folder / str(level) / f"u{r}_{c}.{m['extension']}"),
                         np.ascontiguousarray(face[r * t:(r + 1) * t, c * t:(c + 1) * t]), overwrite=True)


def browser(work, base_url):
    work = pathlib.Path(work).resolve()
    src = pp.read(str(SAMPLE))
    pages = {}
    for viewer in ("pannellum", "marzipano"):
        out = work / viewer
        shutil.rmtree(out, ignore_errors=True)
        script = "../node_modules/pannellum/build/" if viewer == "pannellum" else "../node_modules/marzipano/dist/"
        subprocess.run([CLI, "tiles", str(SAMPLE), str(out), "--viewer", viewer, "--script-url", script, "-q"], check=True)
        pages[viewer] = out
    wrong = work / "pannellum_up_turned"
    shutil.rmtree(wrong, ignore_errors=True)
    shutil.copytree(pages["pannellum"], wrong)
    turn_up_face(wrong, json.loads((wrong / "config.json").read_text()))
    pages["pannellum_up_turned"] = wrong
    jobs = []
    for name in pages:
        for yaw, pitch, hfov in VIEWS:
            jobs.append({"page": f"{name}/index.html", "yaw": yaw, "pitch": pitch, "hfov": hfov,
                         "out": str(work / "shots" / f"{name}_{yaw}_{pitch}_{hfov}.png")})
    (work / "shots").mkdir(exist_ok=True)
    (work / "jobs.json").write_text(json.dumps(jobs))
    # (Run from the work folder, where npm put playwright-core.)
    shutil.copy(ROOT / "tests/browser/tiles_viewers.mjs", work / "tiles_viewers.mjs")
    subprocess.run(["node", str(work / "tiles_viewers.mjs"), base_url, str(work / "jobs.json")], check=True, cwd=work)
    ok = True
    cubes = {}
    print("\npage                 yaw pitch hfov  level (face px)   dB")
    for job in jobs:
        name = job["page"].split("/")[0]
        viewer = "marzipano" if name == "marzipano" else "pannellum"
        config = json.loads((pages[name] / "config.json").read_text())
        level, size = viewer_level(viewer, config, job["hfov"])
        if size not in cubes:
            cubes[size] = pp.convert(src, "equirect", "cubemap", size=(6 * size, size))
        ref = pp.convert(cubes[size], "cubemap", f"pinhole:hfov={job['hfov']}", size=(800, 600), yaw=job["yaw"],
                         pitch=job["pitch"], interp="bilinear", antialias="off")
        shot = pp.read(job["out"])[..., :3]
        db = psnr(shot, ref)
        sees_up = job["pitch"] > 45
        if name == "pannellum_up_turned":
            verdict = "must fail: " + ("FAILS (good)" if db < 30 else "PASSES (bad)") if sees_up else ""
            ok = ok and (db < 30 if sees_up else db >= 30)
        else:
            verdict = "" if db >= 30 else "FAIL"
            ok = ok and db >= 30
        print(f"{name:20s} {job['yaw']:6g} {job['pitch']:5g} {job['hfov']:4d}  {level:5d} ({size:5d})  {db:6.2f} {verdict}")
    print("\nbrowser oracle:", "PASS" if ok else "FAIL")
    return ok


def big(work, script, python):
    """32768x16384 to a full Pannellum pyramid: panoproj against generate.py + nona, time and peak."""
    work = pathlib.Path(work)
    source = work / "big_32768x16384.jpg"
    if not source.exists():
        small = pp.read(str(SAMPLE))
        big = pp.convert(small, "equirect", "equirect", size=(32768, 16384), interp="bicubic")
        pp.write(str(source), big, quality=90)
        del big
    rows = []
    # JPEG tiles at generate.py's quality (75) on both sides.
    for name, cmd in (("panoproj tiles", [CLI, "tiles", str(source), str(work / "big_ours"), "-q", "--quality", "75"]),
                      ("generate.py + nona", [python, script, str(source), "-o", str(work / "big_generate_py")])):
        out = pathlib.Path(cmd[3] if name.startswith("panoproj") else cmd[-1])
        shutil.rmtree(out, ignore_errors=True)
        wrapped = ["/usr/bin/time", "-f", "%e %M"] + cmd
        p = subprocess.run(wrapped, capture_output=True, text=True)
        if p.returncode != 0:
            print(p.stderr[-2000:])
            return False
        seconds, kb = p.stderr.strip().splitlines()[-1].split()
        rows.append((name, float(seconds), int(kb) / 1024))
        print(f"{name:20s} {float(seconds):8.1f} s  peak {int(kb) / 1024:8.0f} MB")
    print(f"ratio (generate.py / panoproj): {rows[1][1] / rows[0][1]:.1f}x time, {rows[1][2] / rows[0][2]:.1f}x peak memory")
    return dask_run(work, source, work / "big_ours", ["--quality", "75"])


def digests(folder):
    import hashlib
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(pathlib.Path(folder).rglob("*")) if p.is_file()}


def _peak_rss_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def dask_run(work, source, local, args):
    """The same pyramid on a 2-worker LocalCluster (one thread each): time, each worker's peak
    memory, and the bytes against the local run's."""
    from dask.distributed import Client, LocalCluster
    out = work / "big_dask"
    shutil.rmtree(out, ignore_errors=True)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                      memory_limit=0) as cluster, Client(cluster) as client:
        t0 = time.perf_counter()
        report = pp.tiles(str(source), str(out), quality=75, client=client, threads=1)
        seconds = time.perf_counter() - t0
        peaks = client.run(_peak_rss_mb)
    same = digests(out) == digests(local)
    print(f"dask LocalCluster 2 workers x 1 thread: {seconds:.1f} s, {report['tasks']} tasks, worker peaks "
          + ", ".join(f"{v:.0f} MB" for v in peaks.values()) + f"; bytes equal to the local run: {same}")
    return same


if __name__ == "__main__":
    what = sys.argv[1]
    if what == "generate-py":
        sys.exit(0 if generate_py(*sys.argv[2:5]) else 1)
    if what == "browser":
        sys.exit(0 if browser(*sys.argv[2:4]) else 1)
    if what == "big":
        sys.exit(0 if big(*sys.argv[2:5]) else 1)
    sys.exit(__doc__)
