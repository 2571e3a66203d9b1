"""A Hugin project's layers: panoproj stitch against nona -m TIFF_m (issues 50 and 51's figures),
and its blended panorama against nona -m TIFF_m followed by enblend (issue 52's):

    scripts/bench.sh stitch [--runs N] [--only none,deflate,float,photometry,photometry-float,feather,multiband]

The project is made here from the real Jordan Pond panorama (samples/images/): six 2400x1600
rectilinear views (hfov 75, 60 degrees apart, JPEG) and two 1600x1600 equidistant fisheyes (180,
up and down), with a b c d e g t non-zero and an S crop, onto a 6000x3000 equirect; both sides
bilinear (m i5), no antialiasing, the same layers (8-bit RGBA, r:CROP) with the same compression:
none, Deflate, and float samples (nona -p FLOAT). photometry and photometry-float: the same with
every photometric value non-trivial (EMoR response, exposures, white balance, vignetting), timed
against the same project without them (the photometric path's cost) and against nona. feather and
multiband: `stitch project.pto pano.tif` (--blend multiband) against `nona -m TIFF_m` then
`enblend -o pano.tif` on its layers (enblend's defaults), the two timed together. The whole
process each, interleaved, --runs times: medians with the spread (min-max), and the ratio per run.
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

ROOT = pathlib.Path(__file__).resolve().parents[1]
BUILD = pathlib.Path(os.environ.get("PANOPROJ_BENCH_BUILD", ROOT / "build-bench"))  # (another Release build)
CLI = BUILD / "tools" / "panoproj"
SOURCE = ROOT / "samples" / "images" / "jordan_pond_4096x2048.jpg"
DIST = dict(a=0.004, b=-0.012, c=0.003, d=8, e=-5, g=2, t=-1)
PLAIN = "Ra0 Rb0 Rc0 Rd0 Re0 Eev0 Er1 Eb1 Va1 Vb0 Vc0 Vd0 Vx0 Vy0 Vm5"
CAMERA = "Ra0.5 Rb-0.3 Rc0.2 Rd0.1 Re-0.05 Eev{ev} Er1.1 Eb0.9 Va1 Vb-0.3 Vc0.1 Vd-0.05 Vx20 Vy-10 Vm5"


def make_project(work, compression, photometric=False):
    lines = [f'p f2 w6000 h3000 v360 E0 R0 n"TIFF_m c:{compression} r:CROP"', "m i5"]
    views = [(0, "rectilinear", 75, y, 0, 2400, 1600) for y in range(0, 360, 60)]
    views += [(3, "equidistant", 180, 0, 90, 1600, 1600), (3, "equidistant", 180, 0, -90, 1600, 1600)]
    for k, (f, lens, v, yaw, pitch, w, h) in enumerate(views):
        name = work / f"v{k}.jpg"
        if not name.exists():
            spec = f"panotools:lens={lens},hfov={v}," + ",".join(f"{a}={b}" for a, b in DIST.items())
            subprocess.run([CLI, "convert", SOURCE, name, "--from", "equirect", "--to", spec, "--size", f"{w}x{h}",
                            "--yaw", str(yaw), "--pitch", str(pitch), "--quiet", "--overwrite"], check=True)
        dist = " ".join(f"{a}{b}" for a, b in DIST.items())
        photometry = CAMERA.format(ev=0.3 * (k % 3)) if photometric else PLAIN
        lines.append(f"i w{w} h{h} f{f} v{v} {photometry} r0 p{pitch} y{yaw} TrX0 TrY0 TrZ0 Tpy0 Tpp0 j0 {dist} "
                     f"S10,{w - 10},10,{h - 10} n\"{name.name}\"")
    project = work / f"project_{compression}{'_photometric' if photometric else ''}.pto"
    project.write_text("\n".join(lines) + "\n")
    return project


def timed(cmd):
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, capture_output=True)
    return time.perf_counter() - t0


def spread(xs):
    return f"{statistics.median(xs):.3f} ({min(xs):.3f}-{max(xs):.3f})"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=11)
    ap.add_argument("--only", default="none,deflate,float,photometry,photometry-float,feather,multiband")
    args = ap.parse_args()
    if shutil.which("nona") is None:
        sys.exit("bench_stitch: nona (apt's hugin-tools) is not installed")
    blends = {"feather": [], "multiband": ["--blend", "multiband"]}
    if any(b in args.only.split(",") for b in blends) and shutil.which("enblend") is None:
        sys.exit("bench_stitch: enblend (apt's enblend) is not installed")
    with tempfile.TemporaryDirectory() as tmp:
        work = pathlib.Path(tmp)
        cases = {"none": ("NONE", [], [], False), "deflate": ("DEFLATE", [], [], False),
                 "float": ("NONE", ["-p", "FLOAT"], ["--depth", "float"], False),
                 "photometry": ("NONE", [], [], True),
                 "photometry-float": ("NONE", ["-p", "FLOAT"], ["--depth", "float"], True)}
        print(f"{args.runs} interleaved runs each; seconds, median (min-max); ratio nona / panoproj per run")
        for name in args.only.split(","):
            if name in blends:
                blend(work, name, blends[name], args.runs)
                continue
            compression, nona_args, our_args, photometric = cases[name]
            project = make_project(work, compression, photometric)
            ours = [CLI, "stitch", project, work / "q_", "--overwrite", "--quiet", *our_args]
            nona = ["nona", *nona_args, "-m", "TIFF_m", "-o", work / "n_", project]
            plain = [CLI, "stitch", make_project(work, compression), work / "p_", "--overwrite", "--quiet",
                     *our_args] if photometric else None
            timed(ours), timed(nona)  # warm the page cache
            t_ours, t_nona, t_plain = [], [], []
            for _ in range(args.runs):
                t_nona.append(timed(nona))
                t_ours.append(timed(ours))
                if plain:
                    t_plain.append(timed(plain))
            ratios = [n / o for n, o in zip(t_nona, t_ours)]
            size = sum(p.stat().st_size for p in work.glob("q_*.tif")) >> 20
            print(f"{name:8s} (8 images, 6000x3000, {size} MB of layers): panoproj {spread(t_ours)} s, "
                  f"nona {spread(t_nona)} s, nona / panoproj {spread(ratios)}")
            if plain:
                cost = [o / p for o, p in zip(t_ours, t_plain)]
                print(f"{'':8s} the same without photometry: panoproj {spread(t_plain)} s; "
                      f"photometric / plain {spread(cost)}")


def blend(work, name, our_args, runs):
    project = make_project(work, "NONE")
    ours = [CLI, "stitch", project, work / "pano.tif", "--overwrite", "--quiet", *our_args]

    def peers():
        for old in work.glob("n_*.tif"):
            old.unlink()
        return timed(["nona", "-m", "TIFF_m", "-o", work / "n_", project]) + \
            timed(["enblend", "-o", work / "enblend.tif", *sorted(work.glob("n_*.tif"))])

    timed(ours), peers()  # warm the page cache
    t_ours, t_peers = [], []
    for _ in range(runs):
        t_peers.append(peers())
        t_ours.append(timed(ours))
    ratios = [n / o for n, o in zip(t_peers, t_ours)]
    print(f"{name:8s} (8 images onto 6000x3000, one blended TIFF): panoproj {spread(t_ours)} s, "
          f"nona + enblend {spread(t_peers)} s, (nona + enblend) / panoproj {spread(ratios)}")


if __name__ == "__main__":
    main()
