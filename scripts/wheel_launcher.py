"""Replaces the launcher auditwheel writes for the wheel's command (it runs
sysconfig.get_path("platlib")/panoproj.scripts/panoproj: only the interpreter's own site-packages,
so `pip install --target DIR` or a launcher run by another interpreter fails) with one that looks
beside itself (DIR/bin/../panoproj.scripts: --target) and then on sys.path (a venv, --user,
PYTHONPATH), and updates the wheel's RECORD.
Usage: python scripts/wheel_launcher.py WHEEL..."""
import base64
import hashlib
import sys
import zipfile

LAUNCHER = b'''#!python
# The panoproj command: runs the executable installed beside the package (panoproj.scripts/).
import os
import sys

here = os.path.dirname(os.path.realpath(__file__))
for folder in [os.path.dirname(here)] + sys.path:
    exe = os.path.join(folder or os.curdir, "panoproj.scripts", "panoproj")
    if os.path.isfile(exe) and os.access(exe, os.X_OK):
        os.execv(exe, [exe] + sys.argv[1:])
sys.exit("panoproj: its executable (panoproj.scripts/panoproj) is neither beside " + here +
         " nor on sys.path (reinstall: pip install --force-reinstall panoproj)")
'''


def record_line(name: str, data: bytes) -> str:
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{name},sha256={digest},{len(data)}"


def fix(path: str) -> None:
    with zipfile.ZipFile(path) as z:
        items = [(i, z.read(i.filename)) for i in z.infolist()]
    launchers = [i.filename for i, _ in items if i.filename.endswith(".data/scripts/panoproj")]
    if len(launchers) != 1:
        sys.exit(f"wheel_launcher: {path} has {len(launchers)} launchers (expected one)")
    record = next(i.filename for i, _ in items if i.filename.endswith(".dist-info/RECORD"))
    with zipfile.ZipFile(path + ".tmp", "w", zipfile.ZIP_DEFLATED) as out:
        for info, data in items:
            if info.filename == launchers[0]:
                data = LAUNCHER
            elif info.filename == record:
                lines = [record_line(launchers[0], LAUNCHER) if line.startswith(launchers[0] + ",") else line
                         for line in data.decode().splitlines()]
                data = ("\n".join(lines) + "\n").encode()
            out.writestr(info, data)
    import os
    os.replace(path + ".tmp", path)


if __name__ == "__main__":
    for wheel in sys.argv[1:]:
        fix(wheel)
