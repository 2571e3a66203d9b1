"""The C++ package (issue 55): `cmake --install` of the build tree gives libpanoproj.so, the
public headers, panoprojConfig.cmake (panoproj::panoproj) with its version file, and panoproj.pc.
The prefix is then moved, and examples/cpp_consumer is built against it twice (CMake's
find_package, and pkg-config with g++ alone); it reads an EXR through the OpenImageIO plugin
installed beside the library and renders the same bytes as the Python module."""
import os
import shutil
import subprocess

import numpy as np
import pytest

import panoproj as pp

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXR = os.path.join(ROOT, "samples", "images", "blender_city_1024x512.exr")


@pytest.fixture(scope="module")
def prefix(cli, tmp_path_factory):
    build = os.path.dirname(os.path.dirname(os.path.abspath(cli)))
    if not os.path.exists(os.path.join(build, "CMakeCache.txt")) or \
            not os.path.exists(os.path.join(build, "lib", "libpanoproj.so")):
        pytest.skip("needs the build tree of scripts/build.sh (PANOPROJ_CLI in it) with libpanoproj.so")
    where = tmp_path_factory.mktemp("package")
    subprocess.run(["cmake", "--install", build, "--prefix", str(where / "installed")], check=True,
                   capture_output=True)
    moved = where / "moved"
    shutil.move(str(where / "installed"), str(moved))  # the package does not depend on where it was installed
    return moved


def test_the_installed_tree(prefix):
    libdir = next(p for p in (prefix / "lib", prefix / "lib64") if (p / "libpanoproj.so").exists())
    assert (libdir / "cmake" / "panoproj" / "panoprojConfig.cmake").exists()
    assert (libdir / "cmake" / "panoproj" / "panoprojConfigVersion.cmake").exists()
    assert (libdir / "pkgconfig" / "panoproj.pc").exists()
    assert (libdir / "panoproj" / "libpanoproj_oiio.so").exists()
    headers = sorted(p.relative_to(prefix / "include").as_posix() for p in (prefix / "include").rglob("*.hpp"))
    expected = sorted(p.relative_to(os.path.join(ROOT, "lib", "include")).as_posix()
                      for p in __import__("pathlib").Path(ROOT, "lib", "include").rglob("*.hpp"))
    assert headers == expected
    # The library hides its dependencies but Eigen (header-only): libjpeg, libpng, zlib, libstdc++ ...
    needed = subprocess.run(["readelf", "-d", str(libdir / "libpanoproj.so")], capture_output=True, text=True,
                            check=True).stdout
    assert "libOpenImageIO" not in needed and "libavformat" not in needed


def consumer_matches(exe, tmp_path):
    out = tmp_path / "view.png"
    r = subprocess.run([str(exe), EXR, str(out), "pinhole:hfov=100"], capture_output=True, text=True, check=True)
    assert r.stdout.startswith(f"panoproj {pp.__version__}: "), r.stdout
    ours = pp.convert(pp.read(EXR), "equirect", "pinhole:hfov=100", size=(320, 240))
    with pytest.warns(UserWarning, match="samples clipped"):  # (an HDR scene into 16 bits, as the consumer's)
        pp.write(str(tmp_path / "python.png"), ours)
    assert np.array_equal(pp.read(str(out)), pp.read(str(tmp_path / "python.png")))
    bad = subprocess.run([str(exe), str(tmp_path / "missing.exr"), str(out)], capture_output=True, text=True)
    assert bad.returncode == 1 and "missing.exr does not exist" in bad.stderr


def test_a_cmake_consumer_builds_against_the_moved_prefix(prefix, tmp_path):
    b = tmp_path / "b"
    subprocess.run(["cmake", "-S", os.path.join(ROOT, "examples", "cpp_consumer"), "-B", str(b), "-G", "Ninja",
                    f"-DCMAKE_PREFIX_PATH={prefix}", "-DCMAKE_BUILD_TYPE=Release"], check=True, capture_output=True)
    r = subprocess.run(["cmake", "--build", str(b)], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    consumer_matches(b / "consumer", tmp_path)
    # SameMinorVersion: asking for 0.2 (or 1.0) is refused at configure time.
    (tmp_path / "newer").mkdir()
    (tmp_path / "newer" / "CMakeLists.txt").write_text(
        "cmake_minimum_required(VERSION 3.25)\nproject(p LANGUAGES CXX)\nfind_package(panoproj 0.2 REQUIRED)\n")
    r = subprocess.run(["cmake", "-S", str(tmp_path / "newer"), "-B", str(tmp_path / "nb"),
                        f"-DCMAKE_PREFIX_PATH={prefix}"], capture_output=True, text=True)
    assert r.returncode != 0 and "panoproj" in r.stderr


def test_a_pkg_config_consumer(prefix, tmp_path):
    libdir = next(p for p in (prefix / "lib", prefix / "lib64") if (p / "libpanoproj.so").exists())
    env = {**os.environ, "PKG_CONFIG_PATH": str(libdir / "pkgconfig")}
    flags = subprocess.run(["pkg-config", "--cflags", "--libs", "panoproj"], capture_output=True, text=True,
                           env=env, check=True).stdout.split()
    exe = tmp_path / "consumer"
    subprocess.run(["g++", "-O1", os.path.join(ROOT, "examples", "cpp_consumer", "main.cpp"), "-o", str(exe), *flags],
                   check=True, capture_output=True)
    consumer_matches(exe, tmp_path)
