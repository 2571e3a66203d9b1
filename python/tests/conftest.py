"""Shared fixtures: the sample images (in the repository) and the CLI built beside the module."""
import os
import pathlib
import shutil
import struct
import sysconfig

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SAMPLES = ROOT / "samples" / "images"


def installed_cli():
    """The panoproj command pip installed with the package into this environment, if any."""
    path = pathlib.Path(sysconfig.get_path("scripts")) / "panoproj"
    return str(path) if path.is_file() and os.access(path, os.X_OK) else None


def native_command(cli):
    """The executable a wheel's launcher script runs (panoproj.scripts/panoproj beside the
    package), else `cli` itself."""
    with open(cli, "rb") as f:
        if f.read(2) != b"#!":
            return cli
    import panoproj
    native = pathlib.Path(panoproj.__file__).parent.parent / "panoproj.scripts" / "panoproj"
    return str(native) if native.is_file() else cli


def runs_as_nobody(executable):
    """Whether `executable` starts as user nobody (setpriv; an interpreter under root's home
    whose libpython nobody cannot read does not)."""
    import subprocess
    args = ["--version"] if "python" not in os.path.basename(executable) else ["-c", "pass"]
    return shutil.which("setpriv") is not None and subprocess.run(
        ["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups", executable, *args],
        capture_output=True).returncode == 0


@pytest.fixture(scope="session")
def cli():
    """The panoproj command of the same build: PANOPROJ_CLI (scripts/test.sh sets it for the build
    tree), else the one installed with the package, else the one on PATH."""
    path = os.environ.get("PANOPROJ_CLI") or installed_cli() or shutil.which("panoproj")
    if not path:
        pytest.fail("PANOPROJ_CLI is not set and panoproj is neither installed here nor on PATH (run scripts/test.sh)")
    return path


@pytest.fixture(scope="session")
def pond():
    return str(SAMPLES / "jordan_pond_4096x2048.jpg")


@pytest.fixture(scope="session")
def pond_faces():
    return str(SAMPLES / "cubemap_jordan_pond" / "face{index}_{face}.jpg")


def child_env(pyav_only=False):
    """The environment of a Python child process: this panoproj first on its path; with
    pyav_only, its video plugin unloadable (video through PyAV, as the wheel without the system's
    FFmpeg libraries)."""
    import panoproj
    package = os.path.dirname(os.path.dirname(panoproj.__file__))
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([package, os.environ.get("PYTHONPATH", "")])}
    if pyav_only:
        env["PANOPROJ_VIDEO_PLUGIN"] = "/nonexistent/libpanoproj_video.so"
    return env


def smooth_equirect(w, h, dtype=np.uint8, channels=3):
    """A smooth scene on the sphere, sampled at equirect pixel centres: slopes up to ~9 per
    radian (at 1024 px: ~0.05 per pixel, so half a pixel moves it by ~2.5 LSB) and curvature so
    small that bilinear interpolation is near exact and cv2.remap's 1/32 px rounding < 0.2 LSB."""
    lon = (np.arange(w) + 0.5) / w * 2 * np.pi - np.pi
    lat = np.pi / 2 - (np.arange(h) + 0.5) / h * np.pi
    lon, lat = np.meshgrid(lon, lat)
    x, y, z = np.cos(lat) * np.sin(lon), np.sin(lat), np.cos(lat) * np.cos(lon)
    planes = [0.5 + 0.4 * np.sin(6.0 * x + 5.0 * y + c) * np.cos(4.0 * z - c) for c in range(channels)]
    img = np.stack(planes, axis=-1)
    if np.issubdtype(dtype, np.integer):
        img = np.round(img * np.iinfo(dtype).max)
    return np.ascontiguousarray(img.astype(dtype))


def pytest_configure(config):
    config.addinivalue_line("markers", "why: reproduces a failure the code once had (test_robustness.py)")


# Hostile files: small, declaring gigapixel images (test_robustness.py, test_io_paths.py).
def huge_tiff():
    """A 1 kB TIFF declaring 100000 x 40000 RGB (one IFD, one strip past the end)."""
    tags = [(256, 4, 100000), (257, 4, 40000), (258, 3, 8), (259, 3, 1), (262, 3, 2), (273, 4, 200),
            (277, 3, 3), (278, 4, 40000), (279, 4, 12000000000 % 2**32)]
    t = b"II*\0" + struct.pack("<I", 8) + struct.pack("<H", len(tags))
    for tag, typ, v in tags:
        t += struct.pack("<HHI", tag, typ, 1) + (struct.pack("<HH", v, 0) if typ == 3 else struct.pack("<I", v))
    return t + struct.pack("<I", 0) + b"\0" * (1024 - len(t) - 4)


def huge_exr(exr):
    """The EXR file's bytes with its dataWindow and displayWindow patched to 0..999999 x 0..999999."""
    e = bytearray(exr)
    for name in (b"dataWindow", b"displayWindow"):
        at = e.find(name + b"\0box2i\0") + len(name) + 1 + 6 + 4
        e[at:at + 16] = struct.pack("<iiii", 0, 0, 999999, 999999)
    return bytes(e)


HUGE_HDR = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1000000 +X 1000000\n" + b"\x02" * 64


def pytest_collection_modifyitems(items):
    """test_compat.py grows this process to ~700 MB (4096x2048 conversions in both libraries), and a
    child forked after that starts with it as its peak (ru_maxrss), which the robustness suite
    measures: it runs last."""
    items.sort(key=lambda item: pathlib.Path(str(item.fspath)).name == "test_compat.py")
