#!/usr/bin/env bash
# The repaired wheel as a user gets it (a CI stage, ~3 min): built by scripts/wheel.sh, installed
# into a fresh virtual environment, checked to resolve no system imaging library, its command run
# from the environment's bin, the whole pytest suite run against it with no environment variable,
# and, where a mount namespace can be made (root), the module used with the system's OpenImageIO
# really gone, then FFmpeg's libraries too (video through PyAV, the av extra). Prints the wheel's
# size and tag, and import time and memory.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
chmod 755 "$work"  # (a robustness test runs the command as another user)
trap 'rm -rf "$work"' EXIT
bash "$root/scripts/wheel.sh" "$work/dist" >/dev/null
wheel=$(ls "$work"/dist/panoproj-*.whl)
echo "wheel: $(basename "$wheel"), $(( $(stat -c %s "$wheel") / 1024 )) kB"
python3 -m venv "$work/venv"
py="$work/venv/bin/python"
"$py" -m pip install -q "$wheel[io,av,test]"
site=$("$py" -c 'import sysconfig; print(sysconfig.get_path("platlib"))')
# The extension and the command: every imaging library their own copy in panoproj.libs.
for elf in "$site"/panoproj/_core*.so "$site/panoproj.scripts/panoproj"; do
  if ldd "$elf" | grep -E 'lib(jpeg|png|tiff|OpenImageIO|hwy|Imath|webp|heif|openjp|raw)' | grep -v panoproj.libs; then
    echo "test-wheel: $elf resolves a system imaging library (above)" >&2
    exit 1
  fi
done
cd "$work"  # away from the source tree
"$work/venv/bin/panoproj" --version
"$work/venv/bin/panoproj" info >/dev/null
"$work/venv/bin/panoproj" convert "$root/samples/images/jordan_pond_4096x2048.jpg" "$work/cube.jpg" --to cubemap --size 1536x256
env -u PANOPROJ_CLI "$py" -m pytest -q -n 2 -p no:cacheprovider "$root/python/tests"
# A clip for the run without FFmpeg's libraries (made while they are here).
ffmpeg -v error -f lavfi -i testsrc2=s=512x256:d=1:r=10 -f lavfi -i sine=d=1 -c:v libx264 -pix_fmt yuv420p \
  -c:a aac -shortest "$work/clip.mp4"
# OpenImageIO gone, then FFmpeg's libraries: covered by empty files in a private mount namespace.
if unshare -m true 2>/dev/null; then
  unshare -m bash -c '
    for f in $(ldconfig -p | grep -o "/[^ ]*libOpenImageIO[^ ]*"); do mount --bind /dev/null "$(readlink -f "$f")"; done
    "$0" -c "
import sys; sys.modules[\"OpenImageIO\"] = None  # (the package hidden too: an import of it fails)
import numpy as np, panoproj as pp
a = pp.convert(np.zeros((64, 128, 3), np.uint8), \"equirect\", \"cubemap\")
assert pp.read(\"$1/samples/images/jordan_pond_4096x2048.jpg\").shape == (2048, 4096, 3)
try:
    pp.read(\"$1/samples/images/blender_city_1024x512.exr\")
    raise SystemExit(\"an EXR was read without OpenImageIO\")
except OSError as e:
    assert \"\\n\" not in str(e) and \"OpenImageIO\" in str(e) and \"install\" in str(e), e
    print(\"without OpenImageIO: arrays and JPEG work; an EXR:\", e)
"
    "$0" -c "
import panoproj as pp
assert pp.read(\"$1/samples/images/blender_city_1024x512.exr\").shape == (512, 1024, 3)
print(\"without the system OpenImageIO, with the openimageio package: an EXR reads\")
"
    for f in $(ldconfig -p | grep -oE "/[^ ]*lib(avformat|avcodec|avutil|swscale)\.so[^ ]*"); do
      mount --bind /dev/null "$(readlink -f "$f")"
    done
    "$0" -c "
import warnings, panoproj as pp
with warnings.catch_warnings(record=True) as said:
    warnings.simplefilter(\"always\")
    r = pp.convert_file(\"$2/clip.mp4\", \"$2/clip_360.mp4\", dst=\"equirect\", size=(512, 256))
assert r[\"frames\"] == 10, r
print(\"without the system FFmpeg libraries, through PyAV (\" + pp._pyav.version() + \"): 10 frames converted,\",
      \"spherical metadata written:\", repr(r[\"spherical_metadata\"]), \"; warnings:\",
      \"; \".join(str(w.message) for w in said) or \"none\")
assert r[\"spherical_metadata\"] == \"equirectangular\", r
"' "$py" "$root" "$work"
else
  echo "test-wheel: no mount namespace here (not root): the run without OpenImageIO is skipped"
fi
"$py" - <<'PY'
import statistics, subprocess, sys
code = ("import time, resource, numpy; t = time.perf_counter(); import panoproj; "
        "print(time.perf_counter() - t, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)")
runs = [subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
        for _ in range(15)]
ms = statistics.median(float(r[0]) for r in runs) * 1e3
rss = statistics.median(int(r[1]) for r in runs) / 1024
print(f"import panoproj after numpy: {ms:.1f} ms (median of 15; target <= 50); peak RSS {rss:.0f} MB (target < 60)")
PY
