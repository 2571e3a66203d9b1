#!/usr/bin/env bash
# Highway's source, as Debian packages the installed libhwy-dev (upstream tarball plus Debian's
# patches: the same headers), unpacked into .deps/highway-VERSION for CMake to build as a static
# library (CMakeLists.txt). Why: Debian ships libhwy.so only, whose timer calibration at load costs
# 3 ms of every process start, and a wheel must not need it. apt-get fetches the source package
# with deb-src entries made from the system's deb ones, in a private list directory: the system's
# apt setup is left as it is. About 2 s once; nothing when the source is there. Without it (no
# apt, offline) CMake falls back to the system's shared libhwy.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
version=$(dpkg-query -W -f='${Version}' libhwy-dev)  # e.g. 1.0.3-3+deb12u1
upstream=${version%%-*}
dest="$root/.deps/highway-$upstream"
[[ -f $dest/CMakeLists.txt ]] && exit 0
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/lists/partial" "$tmp/parts" "$tmp/get"
# deb822 files (Types: deb -> deb-src) and one-line lists (deb -> deb-src).
for f in /etc/apt/sources.list.d/*.sources; do
  [[ -f $f ]] && sed 's/^Types:.*/Types: deb-src/' "$f" >"$tmp/parts/$(basename "$f")"
done
for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
  [[ -f $f ]] && sed -n 's/^deb /deb-src /p' "$f" >>"$tmp/parts/one-line.list"
done
apt=(apt-get -q -o Dir::Etc::sourcelist=/dev/null -o "Dir::Etc::sourceparts=$tmp/parts"
     -o "Dir::State::Lists=$tmp/lists" -o APT::Sandbox::User=root)
echo "fetch-highway: Debian's source of highway $version" >&2
if ! "${apt[@]}" update >/dev/null || ! (cd "$tmp/get" && "${apt[@]}" source --download-only "highway=$version" >/dev/null); then
  echo "fetch-highway: could not fetch it; CMake builds against the system's libhwy.so" >&2
  exit 0
fi
mkdir -p "$tmp/src"
tar -xzf "$tmp/get/highway_$upstream.orig.tar.gz" -C "$tmp/src"
tar -xJf "$tmp/get/highway_$version.debian.tar.xz" -C "$tmp/src/highway-$upstream"
(cd "$tmp/src/highway-$upstream" &&
  while read -r p; do
    [[ -z $p || $p == \#* ]] || patch -s -p1 <"debian/patches/$p"
  done <debian/patches/series)
mkdir -p "$root/.deps"
mv "$tmp/src/highway-$upstream" "$dest"
