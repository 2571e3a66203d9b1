"""The site's pages (README.md and docs/*.md) run as they are: every shell and Python block runs
in a folder holding the files it names (made here, small: renders of the sample panorama, a
Hugin project, rigs, short videos, a GoPro MAX .360 from the sample strips), with `panoproj` the
command under test, or is marked `<!-- not run: REASON -->` on the line before it. python/README.md
(the Python page) is checked too; its Python blocks run in test_readme.py."""

import os
import pathlib
import re
import shutil
import subprocess
import sys

import numpy as np
import pytest

import panoproj as pp

ROOT = pathlib.Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", ROOT / "python" / "README.md"] + sorted((ROOT / "docs").glob("*.md"))
FENCE = re.compile(r"^```(sh|bash|shell|console|python)\n(.*?)^```", re.M | re.S)
NOT_RUN = re.compile(r"^<!-- not run: (.+) -->$")
# Names some blocks read and others write: copied only where the block reads them.
AS_INPUT = {"pano.jpg": r"(convert|tiles|views)\s+pano\.jpg", "frames": r"frames/\*"}


def _blocks():
    """(page, line, language, code, the not-run reason or None) of every shell and Python block."""
    out = []
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        for m in FENCE.finditer(text):
            before = text[:m.start()].rstrip("\n").rsplit("\n", 1)[-1]
            reason = NOT_RUN.match(before)
            line = text.count("\n", 0, m.start()) + 1
            out.append((page.relative_to(ROOT).as_posix(), line, m.group(1), m.group(2), reason and reason.group(1)))
    return out


BLOCKS = _blocks()
# python/README.md's Python blocks (the Python page) run in test_readme.py, type-checked too.
RUN = [b for b in BLOCKS if b[4] is None and not (b[0] == "python/README.md" and b[2] == "python")]


def _run(args, **kw):
    r = subprocess.run(args, capture_output=True, text=True, timeout=300, **kw)
    assert r.returncode == 0, f"{args}: {r.stderr[-2000:]}"


def _video(frames_from, out, seconds, rate, codec="libx264", size=None):
    scale = ["-vf", f"scale={size}"] if size else []
    _run(["ffmpeg", "-v", "error", "-y", "-loop", "1", "-framerate", str(rate), "-i", str(frames_from), "-t",
          str(seconds), *scale, "-c:v", codec, "-preset", "ultrafast", "-pix_fmt", "yuv420p",
          *(["-x265-params", "log-level=none"] if codec == "libx265" else []), str(out)])


@pytest.fixture(scope="module")
def files(tmp_path_factory, cli):
    """Every file the pages' blocks name."""
    if shutil.which("ffmpeg") is None:
        pytest.skip("ffmpeg (the videos the pages convert are made with it) is not installed")
    d = tmp_path_factory.mktemp("docs_files")
    cli = os.path.abspath(cli)

    def convert(out, to, *args, src=ROOT / "samples/images/jordan_pond_4096x2048.jpg"):
        _run([cli, "convert", str(src), str(d / out), "--to", to, "-q", *args])

    convert("pano.jpg", "equirect", "--size", "1024x512")
    pano = d / "pano.jpg"
    convert("lens.png", "fisheye:fov=210", "--size", "512x512", "--pitch", "-90", src=pano)
    convert("lens.jpg", "fisheye:fov=185", "--size", "512x512", src=pano)
    convert("dual.jpg", "dual-fisheye:fov=200", "--size", "1024x512", src=pano)
    convert("frame.jpg", "dual-fisheye:fov=200", "--size", "3840x1920", src=pano)
    shutil.copy(d / "frame.jpg", d / "frame_0042_raw.jpg")
    convert("vr.jpg", "equirect:stereo=tb", "--size", "1024x1024", src=pano)
    convert("v360.png", "cubemap:layout=3x2,order=rludfb", "--size", "768x512", src=pano)
    (d / "frames").mkdir()
    (d / "shots").mkdir()
    for k in range(3):
        shutil.copy(pano, d / "frames" / f"{k:04d}.jpg")
        convert(f"shots/{k:04d}.png", "fisheye:fov=190", "--size", "512x512", "--yaw", str(10 * k), src=pano)
    # A Hugin project of four views around the horizon, and a template of two.
    lines = []
    for k in range(4):
        convert(f"f{k}.jpg", "pinhole:hfov=100", "--size", "400x300", "--yaw", str(90 * k), src=pano)
        lines.append(f'i w400 h300 f0 v100 y{90 * k} p0 r0 n"f{k}.jpg"\n')
    head = 'p f2 w2048 h1024 v360 E0 R0 n"TIFF_m c:NONE r:CROP"\nm i5\n'
    (d / "project.pto").write_text(head + "".join(lines))
    (d / "template.pto").write_text(head + lines[0].replace("f0.jpg", "t0.jpg") + lines[1].replace("f1.jpg", "t1.jpg"))
    (d / "rig.yaml").write_text(
        "lenses:\n"
        "  - {name: front, spec: 'fisheye:fov=200', input: frame.jpg, rect: 1920x1920+0+0}\n"
        "  - {name: back,  spec: 'fisheye:fov=200', input: frame.jpg, rect: 1920x1920+1920+0, yaw: 180}\n")
    _video(d / "dual.jpg", d / "dual.mp4", 0.3, 10)
    (d / "dual_rig.yaml").write_text(
        "lenses:\n"
        "  - {name: front, spec: 'fisheye:fov=200', input: dual.mp4, rect: 512x512+0+0}\n"
        "  - {name: back,  spec: 'fisheye:fov=200', input: dual.mp4, rect: 512x512+512+0, yaw: 180}\n")
    # Videos: a 95-second equirect clip at a frame every 4 s (the pages cut from 1:30), a
    # dual-fisheye one, and a GoPro MAX .360 (its two HEVC strips of one size, from the samples).
    _video(pano, d / "in.mp4", 95, 0.25, size="512:256")
    _video(d / "dual.jpg", d / "in.mov", 0.3, 10)
    shutil.copy(ROOT / "samples/gopro_max/3k_track0_GS018423_1.jpg", d / "track0.jpg")
    shutil.copy(ROOT / "samples/gopro_max/3k_track5_GS018423_1.jpg", d / "track5.jpg")
    pp.write(str(d / "both.png"), np.ascontiguousarray(np.vstack([pp.read(str(d / "track0.jpg")),
                                                                  pp.read(str(d / "track5.jpg"))])))
    for k in ("0", "5"):
        _video(d / f"track{k}.jpg", d / f"strip{k}.mp4", 0.1, 30, codec="libx265")
    _run(["ffmpeg", "-v", "error", "-y", "-i", str(d / "strip0.mp4"), "-i", str(d / "strip5.mp4"), "-map", "0:v",
          "-map", "1:v", "-c", "copy", "-f", "mp4", str(d / "GS010001.360")])
    return d


def _env(cli, work):
    bin_dir = work / "bin"
    bin_dir.mkdir()
    (bin_dir / "panoproj").symlink_to(cli)
    env = dict(os.environ)
    env["PATH"] = f"{bin_dir}{os.pathsep}{env['PATH']}"
    env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
    return env


def test_every_block_runs_or_says_why_not():
    assert len(BLOCKS) >= 20 and len(RUN) >= 15
    for page, line, _, _, reason in BLOCKS:
        assert reason is None or len(reason.split()) >= 3, f"{page}:{line}: say why the block is not run"


def test_a_marker_stands_right_before_its_block():
    for page in PAGES:
        lines = page.read_text(encoding="utf-8").split("\n")
        for i, line in enumerate(lines):
            if line.startswith("<!-- not run"):
                assert NOT_RUN.match(line) and i + 1 < len(lines) and lines[i + 1].startswith("```"), \
                    f"{page.name}:{i + 1}: a not-run marker must be the line right before a block"


@pytest.mark.parametrize("page,line,language,code", [b[:4] for b in RUN], ids=[f"{b[0]}:{b[1]}" for b in RUN])
def test_block_runs(page, line, language, code, files, cli, tmp_path):
    if language != "python" and "enblend" in code and shutil.which("enblend") is None:
        pytest.skip("enblend is not installed")
    cli = os.path.abspath(cli)
    work = tmp_path / "work"
    work.mkdir()
    for entry in files.iterdir():  # all but names the block writes
        if re.search(AS_INPUT.get(entry.name, ""), code):
            (shutil.copytree if entry.is_dir() else shutil.copy)(entry, work / entry.name)
    (work / "samples").symlink_to(ROOT / "samples")
    (work / "build" / "tools").mkdir(parents=True)
    (work / "build" / "tools" / "panoproj").symlink_to(cli)
    env = _env(cli, tmp_path)
    if language == "python":
        args = [sys.executable, "-c", code]
    else:
        args = ["bash", "-euo", "pipefail", "-c", code]
    r = subprocess.run(args, cwd=work, env=env, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, f"{page}:{line}: {r.stderr[-3000:]}"


def test_the_readmes_links_and_pictures_resolve():
    """The README is the front page on GitHub, outside the site's build: its relative links and
    pictures name files that exist (and anchors that the page's headings make)."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    targets = re.findall(r"\]\(([^)\s]+)\)", text)
    assert len(targets) >= 20
    for target in targets:
        if re.match(r"[a-z]+:", target):
            continue
        path, _, anchor = target.partition("#")
        file = ROOT / path
        assert file.exists(), f"README.md links to {target}: no such file"
        if anchor:
            headings = re.findall(r"^#+ (.+)$", file.read_text(encoding="utf-8"), re.M)
            slugs = {re.sub(r"[^\w\- ]", "", h.lower()).replace(" ", "-") for h in headings}
            assert anchor in slugs, f"README.md links to {target}: no such heading"


def test_the_readme_is_a_front_page():
    assert len((ROOT / "README.md").read_text(encoding="utf-8").splitlines()) <= 250
