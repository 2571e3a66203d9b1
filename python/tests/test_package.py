"""The package as pip installs it: its version, and the panoproj command that comes with it."""
import importlib.metadata
import os
import subprocess

import pytest

import panoproj as pp
from conftest import installed_cli


def installed():
    try:
        return importlib.metadata.version("panoproj")
    except importlib.metadata.PackageNotFoundError:
        return None


def test_the_version_is_the_metadatas_and_the_commands(cli):
    assert pp.__version__.count(".") == 2 and all(p.isdigit() for p in pp.__version__.split("."))
    if installed() is not None:
        assert pp.__version__ == installed()
    out = subprocess.run([cli, "--version"], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "panoproj " + pp.__version__


@pytest.mark.skipif(installed() is None, reason="the package is not installed (build tree)")
def test_pip_installs_the_command_and_it_converts(tmp_path, pond):
    cli = installed_cli()
    assert cli is not None, "no panoproj among the environment's scripts"
    # The executable itself (a source install), or auditwheel's launcher of it (a repaired wheel).
    with open(cli, "rb") as f:
        head = f.read(4)
    assert head == b"\x7fELF" or head.startswith(b"#!")
    out = tmp_path / "cube.jpg"
    subprocess.run([cli, "convert", pond, str(out), "--to", "cubemap", "--size", "384x64", "-q"], check=True)
    assert pp.read(str(out)).shape == (64, 384, 3)
    info = subprocess.run([cli, "info"], capture_output=True, text=True, check=True).stdout
    assert "equirect" in info and "cubemap" in info
    # TIFF goes through the OpenImageIO plugin installed beside the command (bin/ -> lib/panoproj/).
    tif = tmp_path / "cube.tif"
    subprocess.run([cli, "convert", str(out), str(tif), "--from", "cubemap", "--to", "equirect",
                    "--size", "128x64", "-q"], check=True)
    assert os.path.getsize(tif) > 0
