#!/usr/bin/env bash
# Installs the Debian packages panoproj needs, only those missing (about a second when none is).
# Usage: scripts/install-deps.sh [more packages, e.g. clang for the fuzz build]
set -euo pipefail

pkgs=(
  g++ cmake ninja-build pkg-config   # toolchain
  libopenimageio-dev                 # TIFF, EXR, HDR and metadata by name (the plugin lib/src/io/oiio)
  libjpeg62-turbo-dev libpng-dev     # JPEG and PNG, built in (lib/src/io)
  libavformat-dev libavcodec-dev libavutil-dev libswscale-dev  # video (the plugin lib/src/io/video)
  libeigen3-dev                      # rotations
  libcli11-dev                       # the panoproj command
  libhwy-dev                         # SIMD kernels (Google Highway)
  libgtest-dev                       # ctest suite
  libopencv-core-dev libopencv-imgproc-dev  # test oracle and bench peer (not the library)
  python3 python3-venv python3-dev   # Python module (venv for Debian's own python3; headers)
  ccache                             # fast rebuilds; used only when present
  fonts-dejavu-core                  # the labels of panoproj accuracy's plots
  "$@"
)

missing=()
for p in "${pkgs[@]}"; do
  # dpkg-query is ~10 ms a package: the whole check stays well under a second.
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q '^install ok installed'; then
    missing+=("$p")
  fi
done
# Highway's source for a static build (CMakeLists.txt), once.
fetch_highway() { bash "$(dirname "$0")/fetch-highway.sh"; }
if ((${#missing[@]} == 0)); then
  fetch_highway
  exit 0
fi

echo "install-deps: installing ${missing[*]}" >&2
sudo=""
if [[ $(id -u) -ne 0 ]]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
apt_get() { $sudo apt-get -y -q -o DPkg::Lock::Timeout=600 "$@"; }
# Update the lists only when a package has no candidate (fresh machine, stale lists).
need_update=0
for p in "${missing[@]}"; do
  cand=$(apt-cache policy "$p" 2>/dev/null | awk '/Candidate:/ {print $2}')
  if [[ -z $cand || $cand == "(none)" ]]; then need_update=1; break; fi
done
((need_update)) && apt_get update
apt_get install --no-install-recommends "${missing[@]}"
fetch_highway
