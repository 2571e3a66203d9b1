#!/usr/bin/env bash
# Error against run time at the sample sizes (the site's "Error against run time", docs/accuracy.md): `panoproj
# accuracy` on equirect -> cubemap (and EAC), fisheye, Mollweide and Panini, and cubemap (and EAC) -> equirect, for the sharp
# chart scene; tables (Markdown pages of the site, each with its plot), CSV, JSON and plots in docs/accuracy/ (or $1).
# Installs what is missing and builds first. Takes a few minutes (the truth is supersampled).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-"$root/docs/accuracy"}
bash "$root/scripts/build.sh"
pp="$root/build/tools/panoproj"
mkdir -p "$out"
sweep() {  # name, then the command's arguments
  local name=$1
  shift
  { echo "# ${name//_/ }"; echo; echo "![error against time]($name.png)"; echo
    "$pp" accuracy "$@" --csv "$out/$name.csv" --json "$out/$name.json" --plot "$out/$name.png" --overwrite; } |
    tee "$out/$name.md"
}
sweep equirect_to_cubemap --from equirect --from-size 4096x2048 --to cubemap --size 6144x1024 --truth-supersample 4
sweep equirect_to_fisheye --from equirect --from-size 4096x2048 --to fisheye:fov=180 --size 512x512
sweep cubemap_to_equirect --from cubemap --from-size 6144x1024 --to equirect --size 4096x2048 --truth-supersample 4
sweep equirect_to_eac --from equirect --from-size 4096x2048 --to cubemap:layout=eac --size 3072x2048 --truth-supersample 4
sweep eac_to_equirect --from cubemap:layout=eac --from-size 3072x2048 --to equirect --size 4096x2048 --truth-supersample 4
sweep equirect_to_mollweide --from equirect --from-size 4096x2048 --to mollweide --size 2048x1024
sweep equirect_to_panini --from equirect --from-size 4096x2048 --to panini:hfov=150 --size 1920x1080
