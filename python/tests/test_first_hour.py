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
