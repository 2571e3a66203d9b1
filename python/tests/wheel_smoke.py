"""The wheel's smoke set for the interpreters that do not run the whole suite (scripts/test-wheel.sh):
import, convert, read and write, a Plan, tiles, the command; each checked, under 30 s.
Usage: python wheel_smoke.py SAMPLES_DIR WORK_DIR"""
import os
import subprocess
import sys
import time

t0 = time.perf_counter()
import numpy as np  # noqa: E402

import panoproj as pp  # noqa: E402

samples, work = sys.argv[1], sys.argv[2]
pano = pp.read(os.path.join(samples, "jordan_pond_4096x2048.jpg"))
assert pano.shape == (2048, 4096, 3) and pano.dtype == np.uint8
cube = pp.convert(pano, None, "cubemap", size=(1536, 256))
assert cube.shape == (256, 1536, 3) and 40 < cube.mean() < 200
back = pp.Plan("cubemap", "equirect", (1536, 256), size=(512, 256))(cube)
assert back.shape == (256, 512, 3)
small = pp.convert(pano, None, "equirect", size=(512, 256))
assert np.abs(back.astype(int) - small.astype(int)).mean() < 12  # a round trip through 256-px faces
pp.write(os.path.join(work, "cube.png"), cube)
assert np.array_equal(pp.read(os.path.join(work, "cube.png")), cube)
report = pp.tiles(os.path.join(samples, "jordan_pond_4096x2048.jpg"), os.path.join(work, "tiles"), tile=256, levels=1)
assert os.path.exists(os.path.join(work, "tiles", "index.html")) and report["written"] > 0, report
command = os.path.join(os.path.dirname(sys.executable), "panoproj")
r = subprocess.run([command, "convert", os.path.join(samples, "jordan_pond_4096x2048.jpg"),
                    os.path.join(work, "view.jpg"), "--to", "pinhole", "--size", "320x240", "-q"])
assert r.returncode == 0 and pp.read(os.path.join(work, "view.jpg")).shape == (240, 320, 3)
seconds = time.perf_counter() - t0
print(f"smoke on Python {sys.version.split()[0]}: import, convert, read/write, Plan, tiles, the command: "
      f"{seconds:.1f} s")
assert seconds < 30
