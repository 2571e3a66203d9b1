#!/usr/bin/env bash
# The repaired wheels as users get them (a CI stage, ~9 min): built by scripts/wheel.sh (one per
# CPython 3.9 to 3.14 these machines carry), the one of .venv's version installed
# into a fresh virtual environment, checked to resolve no system imaging library, its command run
# from the environment's bin, the whole pytest suite run against it with no environment variable,
# and, where a mount namespace can be made (root), the module used with the system's OpenImageIO
# really gone, then FFmpeg's libraries too (video through PyAV, the av extra); then the whole suite
# on 3.13's wheel, the smoke set (python/tests/wheel_smoke.py) on the others', and the command
# installed with --target and --user. Prints each wheel's size and tag, import times and memory.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
chmod 755 "$work"  # (a robustness test runs the command as another user)
trap 'rm -rf "$work"' EXIT
# One wheel per CPython these machines carry (pyenv's 3.9 to 3.14; .venv's own for its version).
own=$("$root/.venv/bin/python" -c 'import sys; print("%d.%d" % sys.version_info[:2])')
pyenv_root=$(pyenv root 2>/dev/null || echo "$HOME/.pyenv")
declare -A interpreter
for v in 3.9 3.10 3.11 3.12 3.13 3.14; do
  if [[ $v == "$own" ]]; then interpreter[$v]="$root/.venv/bin/python"; continue; fi
  found=$(ls -d "$pyenv_root"/versions/"$v".*/bin/python3 2>/dev/null | sort -V | tail -1 || true)
  [[ -n $found ]] && interpreter[$v]=$found
done
versions=$(printf '%s\n' "${!interpreter[@]}" | sort -V)
PANOPROJ_WHEEL_PYTHONS="$(for v in $versions; do printf '%s ' "${interpreter[$v]}"; done)" \
  bash "$root/scripts/wheel.sh" "$work/dist" >/dev/null
wheel=$(ls "$work"/dist/panoproj-*-cp${own/./}-*.whl)
for w in "$work"/dist/panoproj-*.whl; do echo "wheel: $(basename "$w"), $(( $(stat -c %s "$w") / 1024 )) kB"; done
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
# The other interpreters: the whole suite on 3.13 (as on .venv's), the smoke set on the rest; each
# with the import time over numpy. Then the command through --target and --user.
import_time() {
  "$1" - <<'PY'
import statistics, subprocess, sys
code = "import time, numpy; t = time.perf_counter(); import panoproj; print(time.perf_counter() - t)"
runs = [float(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout)
        for _ in range(9)]
print(f"Python {sys.version.split()[0]}: import panoproj after numpy {statistics.median(runs) * 1e3:.1f} ms (median of 9)")
PY
}
for v in $versions; do
  [[ $v == "$own" ]] && continue
  w=$(ls "$work"/dist/panoproj-*-cp${v/./}-*.whl)
  "${interpreter[$v]}" -m venv "$work/venv-$v"
  if [[ $v == 3.13 ]]; then
    "$work/venv-$v/bin/python" -m pip install -q "$w[io,av,test]"
    (cd "$work" && env -u PANOPROJ_CLI "$work/venv-$v/bin/python" -m pytest -q -n 2 -p no:cacheprovider -rf \
      "$root/python/tests" | grep -E "^FAILED|passed|failed" | sed "s/^/Python $v, the whole suite: /")
  else
    "$work/venv-$v/bin/python" -m pip install -q "$w"
    mkdir -p "$work/smoke-$v"
    (cd "$work" && "$work/venv-$v/bin/python" "$root/python/tests/wheel_smoke.py" "$root/samples/images" "$work/smoke-$v")
  fi
  import_time "$work/venv-$v/bin/python"
done
# pip install --target DIR and --user: the command runs from DIR/bin and ~/.local/bin, the
# interpreter having no panoproj of its own.
last=$(printf '%s\n' $versions | tail -1)
"${interpreter[$last]}" -m pip install -q --target "$work/target" "$(ls "$work"/dist/panoproj-*-cp${last/./}-*.whl)"
(cd / && "$work/target/bin/panoproj" convert "$root/samples/images/jordan_pond_4096x2048.jpg" "$work/t.png" \
  --to pinhole --size 64x64 -q && echo "pip install --target: its bin/panoproj converts")
PYTHONUSERBASE="$work/user" "${interpreter[$last]}" -m pip install -q --user "$(ls "$work"/dist/panoproj-*-cp${last/./}-*.whl)"
(cd / && PYTHONUSERBASE="$work/user" "$work/user/bin/panoproj" convert "$root/samples/images/jordan_pond_4096x2048.jpg" \
  "$work/u.png" --to pinhole --size 64x64 -q && echo "pip install --user: its bin/panoproj converts")
