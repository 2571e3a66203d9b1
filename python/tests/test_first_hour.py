"""A new user's first hour (issue 55's friction points), each as it was met: the command's texts
instead of CLI11's raw ones, the nearest name for a misspelt command, flag or kernel, a
projection's key given as a flag, sizes as WxH with either x or N for a square, memory limits
with binary units. Each case failed before its fix, but `accuracy_type`, already right when this
began (a guard that it stays so)."""
import subprocess

import numpy as np
import pytest

import panoproj as pp


def error_of(cli, *args):
    r = subprocess.run([cli, *args], capture_output=True, text=True)
    assert r.returncode == 1 and r.stdout == ""
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, lines
    assert lines[0].startswith("panoproj: error: ")
    return lines[0][len("panoproj: error: "):]


COMMON = ["convert", "in.jpg", "out.jpg"]


@pytest.mark.parametrize("args, said", [
    (["frobnicate"], "'frobnicate' is not a command (the commands: convert, maps, tiles, views, "),
    (["convrt", "a", "b"], "'convrt' is not a command (did you mean convert? the commands: convert, "),
    (COMMON + ["--to", "pinhole", "--hfov", "90"],
     "--hfov is not an option of convert: a projection's keys go in its spec (--to pinhole:hfov=90)"),
    (COMMON + ["--to", "fisheye:fov=200", "--model=equisolid"],
     "--model is not an option of convert: a projection's keys go in its spec (--to fisheye:fov=200,model=equisolid)"),
    (COMMON + ["--to", "pinhole", "--interpolation", "bicubic"],
     "--interpolation is not an option of convert (did you mean --interp? see panoproj convert --help)"),
    (COMMON + ["--to", "pinhole", "--interp", "cubic"], "interpolator 'cubic' is unknown (did you mean bicubic? "),
    (["views", "in.jpg", "out", "--yaw", "10"], "--yaw is not an option of views (see panoproj views --help)"),
    (["accuracy", "--to", "pinhole", "--type", "bogus"], "type: bogus (expected uint8, uint16, half or float)"),
    (COMMON + ["--to", "pinhole", "--memory-limit", "1e19"],
     "memory limit: 1e19 (expected at most 9E18 bytes; leave it out for the memory available)"),
    (COMMON + ["--to", "pinhole", "--memory-limit", "4GiBs"],
     "memory limit: 4GiBs (expected a size such as 4G, 4GiB, 512M or 800000000)"),
    (COMMON + ["--to", "pinhole", "--size", "64y"],
     "size: 64y (expected WxH with positive integers, e.g. 2048x1024, or N for a square)"),
], ids=["command", "command_near", "key_as_flag", "key_as_flag_with_spec", "flag_near", "interp_near", "views_yaw",
        "accuracy_type", "memory_huge", "memory_unit", "size"])
def test_the_commands_texts(cli, args, said):
    assert error_of(cli, *args).startswith(said)


@pytest.mark.parametrize("size, expected", [("1024", (1024, 1024)), ("640X480", (640, 480)), ("640x480", (640, 480))])
def test_sizes_as_n_or_either_x(cli, tmp_path, size, expected):
    src = tmp_path / "in.png"
    pp.write(str(src), np.zeros((32, 64, 3), np.uint8))
    out = tmp_path / "out.png"
    subprocess.run([cli, "convert", str(src), str(out), "--to", "pinhole", "--size", size, "-q"], check=True)
    assert pp.read(str(out)).shape[1::-1] == expected
    assert pp.convert(np.zeros((32, 64, 3), np.uint8), "equirect", "pinhole", size=size).shape[1::-1] == expected
    if size == "1024":
        assert pp.convert(np.zeros((32, 64, 3), np.uint8), "equirect", "pinhole", size=1024).shape[:2] == (1024, 1024)


@pytest.mark.parametrize("limit", ["4GiB", "4gib", "3500MiB", "4G", "4GB"])
def test_memory_limits_with_binary_units(cli, tmp_path, limit):
    src = tmp_path / "in.png"
    pp.write(str(src), np.zeros((32, 64, 3), np.uint8))
    subprocess.run([cli, "convert", str(src), str(tmp_path / "out.png"), "--to", "pinhole", "--memory-limit", limit,
                    "-q"], check=True)
    pp.convert(np.zeros((32, 64, 3), np.uint8), "equirect", "pinhole", memory_limit=limit)



def test_dir_lists_the_api_only():
    names = [n for n in dir(pp) if not n.startswith("__")]
    assert names == sorted(pp.__all__)
    assert not {"np", "os", "re", "Any", "Union", "Optional", "ThreadPoolExecutor", "warnings"} & set(dir(pp))
    for n in names:
        getattr(pp, n)


def test_a_dtype_with_metadata_is_its_dtype():
    plain = np.arange(8 * 16 * 3, dtype=np.uint8).reshape(8, 16, 3)
    tagged = plain.astype(np.dtype(np.uint8, metadata={"source": "camera"}))
    assert np.array_equal(pp.convert(tagged, "equirect", "pinhole", size=(8, 8)),
                          pp.convert(plain, "equirect", "pinhole", size=(8, 8)))


def test_an_array_argument_is_shown_by_its_shape():
    with pytest.raises(TypeError) as e:
        pp.convert(np.zeros((8, 16, 3), np.uint8), "equirect", "pinhole", size=np.zeros((100, 100)))
    assert str(e.value) == "size: an array of shape (100, 100) and dtype float64 (expected (width, height))"
    with pytest.raises(ValueError) as e:
        pp.convert(np.zeros((8, 16, 3), np.uint8), "equirect", "pinhole", interp="x" * 500)
    assert len(str(e.value)) < 300


def test_the_projection_list_is_cut_between_words(cli):
    said = error_of(cli, *COMMON, "--to", "zzz")
    assert said.startswith(f"unknown projection 'zzz' (expected one of the {len(pp.projections())} that panoproj "
                           "info lists: pinhole, fisheye, ")
    names = {p.name for p in pp.projections()}
    listed = said.split(" lists: ")[1].removesuffix(" ...").split(", ")
    assert said.endswith(" ...") and listed and all(n in names for n in listed), listed
    with pytest.raises(ValueError, match=r"that panoproj.projections\(\) lists: pinhole, fisheye, .*\)$"):
        pp.convert(np.zeros((8, 16), np.uint8), "equirect", "zzz")


def test_info_names_no_internal_header(cli):
    r = subprocess.run([cli, "info"], capture_output=True, text=True, check=True)
    assert ".hpp" not in r.stdout and ".cpp" not in r.stdout


def test_rig_file_texts_are_printable_and_short(cli, tmp_path):
    """A rig file's raw bytes come back as \\xNN (Python got UnicodeDecodeError), its numbers as
    %g (std::to_string printed 301 digits), long values cut."""
    pano = tmp_path / "p.png"
    pp.write(str(pano), np.zeros((32, 64, 3), np.uint8))
    cases = {"raw.yaml": (b"- {name: a\x01\xff, yaw: 0, hfov: 90}\n", r"name 'a\x01\xFF' (expected 1 to 64"),
             "yaw.yaml": (b"- {name: a, yaw: 1" + b"0" * 300 + b", hfov: 90}\n", "view a: yaw 1e+300 (expected"),
             "key.yaml": (b"- {name: a, " + b"k" * 500 + b": 1}\n", "unknown key '" + "k" * 77 + "...' (expected")}
    for name, (text, said) in cases.items():
        (tmp_path / name).write_bytes(text)
        assert said in error_of(cli, "views", str(pano), str(tmp_path / "o"), "--rig", "@" + str(tmp_path / name))
        with pytest.raises(ValueError) as e:
            pp.views(str(pano), str(tmp_path / "o"), rig="@" + str(tmp_path / name))
        assert said in str(e.value)
    (tmp_path / "bom.yaml").write_bytes(b"\xef\xbb\xbf- {name: a, yaw: 0, hfov: 90}\n")
    subprocess.run([cli, "views", str(pano), str(tmp_path / "v"), "--rig", "@" + str(tmp_path / "bom.yaml"), "-q"],
                   check=True)


def test_a_mono_targets_size_names_no_eyes(cli, tmp_path):
    src = tmp_path / "in.png"
    pp.write(str(src), np.zeros((32, 64, 3), np.uint8))
    assert error_of(cli, "convert", str(src), str(tmp_path / "o.png"), "--to", "cubemap:layout=6x1,face=1000000000"
                    ).startswith("size: 6000000000x1000000000 (expected at most")


def test_face_size_sizes_every_cube_layout(cli, tmp_path):
    """--size is the whole image but for layout=files (one face); --face-size N (face_size=)
    gives N x N faces in any layout; the refusal of a 3x2 size says so."""
    src = tmp_path / "in.png"
    pp.write(str(src), np.zeros((64, 128, 3), np.uint8))
    for layout, grid in [("6x1", (6, 1)), ("3x2", (3, 2)), ("cross", (4, 3)), ("eac", (3, 2)), ("1x6", (1, 6))]:
        out = tmp_path / f"{layout}.png"
        subprocess.run([cli, "convert", str(src), str(out), "--to", f"cubemap:layout={layout}", "--face-size", "24",
                        "-q"], check=True)
        assert pp.read(str(out)).shape[1::-1] == (24 * grid[0], 24 * grid[1])
        a = pp.convert(np.zeros((64, 128, 3), np.uint8), "equirect", f"cubemap:layout={layout}", face_size=24)
        assert a.shape[1::-1] == (24 * grid[0], 24 * grid[1])
    subprocess.run([cli, "convert", str(src), str(tmp_path / "f_{face}.png"), "--to", "cubemap:layout=files",
                    "--face-size", "20", "-q"], check=True)
    assert pp.read(str(tmp_path / "f_front.png")).shape[:2] == (20, 20)
    assert error_of(cli, "convert", str(src), str(tmp_path / "o.png"), "--to", "cubemap:layout=3x2", "--size",
                    "512x512").endswith("(check the size or the layout; a target's --face-size N gives N x N faces)")
    for args, said in [(["--to", "pinhole", "--face-size", "8"], "--face-size 8: pinhole has no faces"),
                       (["--to", "cubemap", "--face-size", "8", "--size", "48x8"], "give --size or --face-size, not both"),
                       (["--to", "cubemap:face=16", "--face-size", "8"], "--face-size 8 and the spec's face=16 differ"),
                       (["--to", "cubemap", "--face-size", "0"], "--face-size 0 (expected 1 to ")]:
        assert error_of(cli, "convert", str(src), str(tmp_path / "o.png"), *args).startswith(said)
    with pytest.raises(ValueError, match="face_size=8: pinhole has no faces"):
        pp.convert(np.zeros((8, 16), np.uint8), "equirect", "pinhole", face_size=8)


def test_a_patterns_missing_folders_are_made(cli, tmp_path):
    """'cube/{face}.jpg' and a batch's '{stem}' pattern make their folders; a single output does
    not (a typo stays an error); a job that fails leaves no folder behind."""
    src = tmp_path / "in.png"
    pp.write(str(src), np.zeros((32, 64, 3), np.uint8))
    subprocess.run([cli, "convert", str(src), str(tmp_path / "cube/a/{face}.png"), "--to", "cubemap:layout=files",
                    "-q"], check=True)
    assert len(list((tmp_path / "cube/a").iterdir())) == 6
    subprocess.run([cli, "convert", str(src), str(src), str(tmp_path / "b/{n}.png"), "--to", "pinhole", "--size", "8",
                    "-q"], check=True)
    assert sorted(p.name for p in (tmp_path / "b").iterdir()) == ["0.png", "1.png"]
    assert error_of(cli, "convert", str(src), str(tmp_path / "c/o.png"), "--to", "pinhole") == \
        f"output folder {tmp_path / 'c'} does not exist (create it first)"
    (tmp_path / "file").write_bytes(b"")
    assert error_of(cli, "convert", str(src), str(tmp_path / "file/d/{face}.png"), "--to", "cubemap:layout=files") == \
        f"output folder {tmp_path / 'file'} is not a folder (give another path)"
    # A face that cannot be written (over the file-size limit) fails the job: no folder is left.
    import resource
    import signal
    noise = tmp_path / "noise.png"
    pp.write(str(noise), np.random.default_rng(1).integers(0, 255, (64, 128, 3), dtype=np.uint8))
    r = subprocess.run([cli, "convert", str(noise), str(tmp_path / "e/f/{face}.png"), "--to", "cubemap:layout=files",
                        "--size", "300"], capture_output=True, text=True,
                       preexec_fn=lambda: (signal.signal(signal.SIGXFSZ, signal.SIG_IGN),
                                           resource.setrlimit(resource.RLIMIT_FSIZE, (4096, 4096))))
    assert r.returncode != 0 and not (tmp_path / "e").exists(), r.stderr


def test_convert_takes_a_path(tmp_path):
    import pathlib
    a = (np.arange(32 * 64 * 3) % 251).astype(np.uint8).reshape(32, 64, 3)
    pp.write(str(tmp_path / "in.png"), a)
    expected = pp.convert(a, None, "pinhole", size=16)
    for path in (str(tmp_path / "in.png"), pathlib.Path(tmp_path / "in.png")):
        np.testing.assert_array_equal(pp.convert(path, None, "pinhole", size=16), expected)
    with pytest.raises(FileNotFoundError, match="nope.png does not exist"):
        pp.convert(str(tmp_path / "nope.png"), None, "pinhole")


def test_what_a_write_loses_is_said(cli, tmp_path):
    """Named warnings where a format drops something: alpha, depth, samples out of range (with the
    count), metadata; once each on stderr, none with -q; Python's as UserWarnings."""
    rgba = np.zeros((32, 64, 4), np.uint8)
    rgba[..., 3] = 128
    pp.write(str(tmp_path / "rgba.png"), rgba)
    hdr = np.full((32, 64, 3), 0.5, np.float32)
    hdr[:4] = 3.0
    pp.write(str(tmp_path / "hdr.exr"), hdr)
    cases = [("rgba.png", "o.jpg", [], "alpha dropped: {out}: JPEG holds no alpha"),
             ("rgba.png", "o.png", ["--depth", "float"], "depth lowered: {out}: PNG holds uint16 samples, not float"),
             ("hdr.exr", "o.png", [], "samples clipped: {out}: "),
             ("rgba.png", "o.ppm", [], "alpha dropped: {out}: PPM/PGM holds no alpha")]
    for src, out, extra, said in cases:
        args = [cli, "convert", str(tmp_path / src), str(tmp_path / out), "--to", "equirect", "--overwrite", *extra]
        r = subprocess.run(args, capture_output=True, text=True, check=True)
        warnings = [line for line in r.stderr.splitlines() if line.startswith("panoproj: warning: ")]
        assert len(warnings) == 1 and said.format(out=tmp_path / out) in warnings[0], r.stderr
        assert subprocess.run(args + ["-q"], capture_output=True, text=True, check=True).stderr == ""
    # The clipped count is the samples outside 0..1: the rows at 3.0 (equirect to equirect, same size).
    r = subprocess.run([cli, "convert", str(tmp_path / "hdr.exr"), str(tmp_path / "o.png"), "--to", "equirect",
                        "--overwrite", "--interp", "nearest"], capture_output=True, text=True, check=True)
    assert f"samples clipped: {tmp_path / 'o.png'}: {4 * 64 * 3} samples (12.5%) outside 0..1" in r.stderr
    with pytest.warns(UserWarning, match="alpha dropped: .*o2.jpg: JPEG holds no alpha"):
        pp.write(str(tmp_path / "o2.jpg"), rgba)
    with pytest.warns(UserWarning, match=r"samples clipped: .*o2.png: 768 samples \(12.5%\) outside 0..1"):
        pp.write(str(tmp_path / "o2.png"), hdr)
    with pytest.warns(UserWarning, match="metadata dropped: .*o2.ppm: PPM/PGM holds no metadata"):
        pp.write(str(tmp_path / "o2.ppm"), rgba[..., :3], metadata={"ImageDescription": "x"})
    with pytest.warns(UserWarning, match="alpha dropped: .*o3.jpg"):
        pp.convert_file(str(tmp_path / "rgba.png"), str(tmp_path / "o3.jpg"), dst="equirect")
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        pp.write(str(tmp_path / "o4.png"), rgba)  # nothing lost: no warning
        pp.write(str(tmp_path / "o4.exr"), hdr)


def test_the_reported_time_includes_encoding(cli, tmp_path):
    """The line's seconds run until the file landed (a 16-bit PNG of noise: its encoding is most
    of the work; before, the line showed the remap alone)."""
    import time
    noise = np.random.default_rng(2).integers(0, 65535, (1024, 2048, 3), dtype=np.uint16)
    pp.write(str(tmp_path / "in.png"), noise)
    t0 = time.perf_counter()
    r = pp.convert_file(str(tmp_path / "in.png"), str(tmp_path / "out.png"), dst="equirect", interp="nearest")
    wall = time.perf_counter() - t0
    t0 = time.perf_counter()
    pp.write(str(tmp_path / "again.png"), pp.read(str(tmp_path / "out.png")))
    encoding = time.perf_counter() - t0
    assert r["frames"][0]["seconds"] >= 0.5 * encoding and r["frames"][0]["seconds"] <= wall, (r, wall, encoding)


def test_an_interrupted_batch_says_what_landed(cli, tmp_path):
    import signal
    import time
    pano = np.random.default_rng(3).integers(0, 255, (1024, 2048, 3), dtype=np.uint8)
    inputs = []
    for i in range(12):
        inputs.append(str(tmp_path / f"in{i:02d}.png"))
        pp.write(inputs[-1], pano)
    p = subprocess.Popen([cli, "convert", *inputs, str(tmp_path / "out/{stem}.png"), "--to", "equirect", "-q"],
                         stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while not (tmp_path / "out").exists() or not any((tmp_path / "out").glob("in*.png")):
        assert time.monotonic() < deadline and p.poll() is None
        time.sleep(0.02)
    p.send_signal(signal.SIGINT)
    err = p.communicate()[1]
    assert p.returncode == -signal.SIGINT
    written = sorted(f.name for f in (tmp_path / "out").iterdir())
    assert err.strip() == f"panoproj: interrupted after {len(written)} of 12; {len(written)} written, each whole, " \
                          "the rest not begun or removed", err
    assert 1 <= len(written) < 12 and all(n.startswith("in") for n in written)


def test_the_default_memory_budget_leaves_a_quarter(cli, tmp_path):
    """Without --memory-limit a job may take 3/4 of the memory available now (at least 1 GiB left
    where there are 2 GiB): the limit a refusal names, against /proc/meminfo's MemAvailable."""
    import re
    avail = next(int(line.split()[1]) * 1024 for line in open("/proc/meminfo") if line.startswith("MemAvailable:"))
    if avail < 4 << 30:
        pytest.skip("under 4 GiB available: the 1 GiB rule decides")
    src = tmp_path / "in.png"
    pp.write(str(src), np.zeros((32, 64, 3), np.uint8))
    side = int((2 * avail / 3) ** 0.5) + 1  # an output of twice what is available
    said = error_of(cli, "convert", str(src), str(tmp_path / "o.png"), "--to", "pinhole", "--size", str(side))
    m = re.search(r"over the memory limit of ([\d.]+) (GB|TB) \(3/4 of the memory available now", said)
    if m is None and "cgroup" in said:
        pytest.skip("a cgroup limits this process more than the machine")
    assert m, said
    limit = float(m.group(1)) * (1e9 if m.group(2) == "GB" else 1e12)
    assert 0.65 * avail < limit < 0.85 * avail, (limit, avail)


REMAP = """
import sys, cv2, numpy as np
m = np.load(sys.argv[1])
out = cv2.remap(np.load(sys.argv[2]), m, None, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT)
np.save(sys.argv[3], out)
print(cv2.__version__)
"""


@pytest.mark.parametrize("line", ["5", "4"])
def test_maps_as_npy_feed_both_opencv_lines(cli, tmp_path, line):
    """`maps m.npy`: np.load gives cv2.remap's CV_32FC2 map; pip's OpenCV 4.x and 5.x both
    reproduce panoproj's bilinear within 1 LSB (the README's recipe; .exr failed with both)."""
    import os
    import sys
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    python = sys.executable if line == "5" else os.path.join(root, ".venv-cv4", "bin", "python")
    if not os.path.exists(python):
        pytest.skip(".venv-cv4 is made by scripts/python-env.sh")
    # A smooth source: cv::remap's bilinear takes positions to 1/32 px.
    y, x = np.mgrid[0:256, 0:512]
    src = np.stack([127 + 100 * np.sin(x / 8 + k) * np.cos(y / 8) for k in range(3)], -1).round().astype(np.uint8)
    np.save(tmp_path / "src.npy", src)
    subprocess.run([cli, "maps", str(tmp_path / "m.npy"), "--from", "equirect", "--source-size", "512x256",
                    "--to", "pinhole:hfov=100", "--size", "300x200", "--yaw", "20", "-q"], check=True)
    r = subprocess.run([python, "-c", REMAP, str(tmp_path / "m.npy"), str(tmp_path / "src.npy"),
                        str(tmp_path / "out.npy")], capture_output=True, text=True, check=True)
    assert r.stdout.startswith(line + "."), r.stdout
    theirs = np.load(tmp_path / "out.npy").astype(int)
    ours = pp.convert(src, "equirect", "pinhole:hfov=100", size=(300, 200), yaw=20, interp="bilinear",
                      antialias="off").astype(int)
    assert np.abs(theirs - ours).max() <= 1
    # A half-pixel slip of the convention would not pass.
    m = np.load(tmp_path / "m.npy")
    assert m.shape == (200, 300, 2) and m.dtype == np.float32
    np.save(tmp_path / "slip.npy", m + 0.5)
    subprocess.run([python, "-c", REMAP, str(tmp_path / "slip.npy"), str(tmp_path / "src.npy"),
                    str(tmp_path / "out2.npy")], capture_output=True, check=True)
    assert np.abs(np.load(tmp_path / "out2.npy").astype(int) - ours).max() > 1


@pytest.mark.parametrize("viewer, script_global, files", [("pannellum", "pannellum", "node_modules/pannellum/build/"),
                                                           ("marzipano", "Marzipano", "node_modules/marzipano/dist/")])
def test_a_tiles_page_says_why_it_is_blank(cli, tmp_path, viewer, script_global, files):
    """Opened from disk, or without its viewer's script (offline, a wrong --script-url), the page
    says why it is blank and how to serve it; the command's line says so too."""
    src = tmp_path / "in.png"
    pp.write(str(src), np.zeros((64, 128, 3), np.uint8))
    r = subprocess.run([cli, "tiles", str(src), str(tmp_path / "t"), "--viewer", viewer, "--tile", "64"],
                       capture_output=True, text=True, check=True)
    assert f"python3 -m http.server -d {tmp_path / 't'}, then http://localhost:8000/" in r.stdout
    assert "offline: --script-url to the viewer's files" in r.stdout
    page = (tmp_path / "t" / "index.html").read_text()
    assert 'if (location.protocol === "file:")' in page and "browsers do not load its tiles from file://" in page
    assert f'typeof {script_global} === "undefined"' in page and files in page
    assert "run python3 -m http.server in it and open http://localhost:8000/" in page
    # The notice comes before the viewer starts (which fails without its script).
    assert page.index('id="why"') < page.index("var q = new URLSearchParams")
    subprocess.run([cli, "tiles", str(src), str(tmp_path / "u"), "--viewer", viewer, "--tile", "64", "-q",
                    "--script-url", "lib/"], check=True)
    page = (tmp_path / "u" / "index.html").read_text()
    assert "did not load from lib/ (offline, or a wrong address)" in page


def test_a_source_build_without_its_packages_stops_at_once_naming_them(tmp_path):
    """CMake's configure, as pip's source build runs it, with two build packages hidden: one line
    naming both Debian packages, in seconds, before anything compiles."""
    import os
    import shutil
    import time
    if shutil.which("cmake") is None:
        pytest.skip("no cmake")
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    t0 = time.perf_counter()
    r = subprocess.run(["cmake", "-S", root, "-B", str(tmp_path / "b"), "-DCMAKE_DISABLE_FIND_PACKAGE_PNG=ON",
                        "-DCMAKE_DISABLE_FIND_PACKAGE_Eigen3=ON", "-DPANOPROJ_BUILD_TESTS=OFF"],
                       capture_output=True, text=True)
    assert r.returncode != 0 and time.perf_counter() - t0 < 30
    said = " ".join(r.stderr.split())
    assert "panoproj needs these Debian packages to build: apt install libeigen3-dev libpng-dev " \
           "(scripts/install-deps.sh installs every build package)" in said, r.stderr
    assert not (tmp_path / "b" / "build.ninja").exists() and not (tmp_path / "b" / "Makefile").exists()


def test_a_misspelt_spec_key_gets_the_nearest(cli):
    assert error_of(cli, *COMMON, "--to", "fisheye:fvo=180").startswith(
        "fisheye: unknown key 'fvo' (did you mean fov? expected one of: fov, model, ")
    with pytest.raises(ValueError, match=r"unknown key 'modle' \(did you mean model\?"):
        pp.convert(np.zeros((8, 16), np.uint8), "equirect", "fisheye:modle=equisolid")
