"""The folder race (robustness suite, scripts/folder-race.sh): a root run of a folder job into a
world-writable folder while an unprivileged process swaps its temporary folder for a link."""
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time


def _swapper(parent, target, seconds):
    """Source of a process that, for `seconds`, moves every temporary folder in `parent` aside and
    puts a link to `target` at its name (what anyone who can write to `parent` can do)."""
    return f"""
import os, time
parent, target, end = {str(parent)!r}, {str(target)!r}, time.time() + {seconds}
while time.time() < end:
    try:
        names = os.listdir(parent)
    except OSError:
        continue
    for n in names:
        if n.startswith(".panoproj-") and n.endswith(".tmp"):
            p = os.path.join(parent, n)
            try:
                if os.path.isdir(p) and not os.path.islink(p):
                    os.rename(p, p + ".moved")
                    os.symlink(target, p)
            except OSError:
                pass
"""


def folder_race(cli, image, command, runs, seconds=10):
    """Runs the job `runs` times as root into a world-writable folder (no sticky bit) while an
    unprivileged swapper (nobody, via setpriv) redirects its temporary folder to a root-only
    folder; returns (runs that left a file in the root-only folder, runs whose temporary folder
    the swapper did swap)."""
    base = pathlib.Path(tempfile.mkdtemp(prefix="panoproj-race-", dir="/tmp"))
    try:
        parent, secret = base / "shared", base / "root-only"
        parent.mkdir()
        secret.mkdir()
        os.chmod(base, 0o755)
        os.chmod(parent, 0o777)
        os.chmod(secret, 0o700)
        src = parent / "in.png"
        shutil.copy(image, src)
        hits = swapped = 0
        for k in range(runs):
            swapper = subprocess.Popen(["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups", sys.executable,
                                        "-c", _swapper(parent, secret, seconds)])
            try:
                time.sleep(0.05)
                subprocess.run([os.path.abspath(cli), command, str(src), str(parent / f"out{k}"), "-q"],
                               capture_output=True, timeout=60)
            finally:
                swapper.kill()
                swapper.wait()
            moved = [p for p in parent.iterdir() if p.name.endswith(".moved")]
            swapped += bool(moved)
            for p in moved:
                shutil.rmtree(p)
            if any(secret.iterdir()):
                hits += 1
                shutil.rmtree(secret)
                secret.mkdir(mode=0o700)
        return hits, swapped
    finally:
        shutil.rmtree(base, ignore_errors=True)


if __name__ == "__main__":
    cli, image, command, runs = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
    hits, swapped = folder_race(cli, image, command, runs)
    print(f"{command}: {hits} of {runs} runs wrote into the root-only folder; the swapper swapped the temporary "
          f"folder in {swapped}")
