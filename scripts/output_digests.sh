#!/usr/bin/env bash
# Prints the SHA-256 of a fixed set of conversions: every projection as target and as source,
# every kernel, every antialiasing mode, the three engines, alpha/fill, float output and maps; every
# case-table spec as target and source; tile and view folders; the write options.
# Run it with the CLI of two commits and diff the lists: a restructuring must leave them equal.
# Usage: scripts/output_digests.sh [PANOPROJ_CLI] > digests.txt   (default: build/tools/panoproj)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cli=$(realpath "${1:-$root/build/tools/panoproj}")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
run() { "$cli" "$@" --quiet --threads 2; }

# A small equirect source (itself a conversion, digested below).
run convert "$root/samples/images/jordan_pond_4096x2048.jpg" --to equirect --size 512x256 --interp bilinear src.png
cp "$root/samples/images/stellarium_trees_fisheye210_512.png" fish.png

# Every catalogue form as target (from the equirect), then back to an equirect (as source).
targets=(
  "pinhole:hfov=100|320x240" "brown-conrady:k1=-0.2,k2=0.05,p1=0.001|320x240" "fisheye:fov=200|256x256"
  "fisheye:fov=180,model=equisolid|256x256" "fisheye:fov=170,model=orthographic,clip=none|256x200"
  "fisheye:fov=300,model=stereographic,aspect=stretch|300x256" "dual-fisheye|512x256" "dual-fisheye:layout=top-bottom,fov=200,feather=10|256x512"
  "kannala-brandt:k1=0.03,k2=-0.01,fov=220|256x256" "double-sphere:xi=-0.2,alpha=0.6|256x256" "unified:xi=0.8|256x256"
  "extended-unified:alpha=0.6,beta=1.1|256x256" "ptlens:a=0.01,b=-0.03,c=0.02|256x256" "equirect:hfov=200,vfov=100,lon0=30,lat0=20|300x150"
  "cylindrical:vfov=120|400x200" "cubemap|768x128" "cubemap:layout=cross|512x384" "cubemap:layout=3x2|384x256" "aitoff|400x200"
  "hammer|400x200" "eckert-greifendorff|400x200" "bonne|400x300" "bonne:phi1=-30,lon0=40|400x300" "bonne:phi1=0|400x300"
)
i=0
for t in "${targets[@]}"; do
  spec=${t%|*} size=${t#*|} i=$((i + 1))
  run convert src.png --to "$spec" --size "$size" --yaw 20 --pitch -10 to_$i.png
  run convert to_$i.png --from "$spec" --to equirect --size 256x128 back_$i.png
done
run convert src.png --to cubemap:layout=files --size 64x64 "face_{face}.png"
run convert "face_{face}.png" --to equirect --size 256x128 from_faces.png

# Every case-table spec (panoproj stability's rows) as target, then as source. Its size: the
# table's smallest size with both sides over 1 px, divided by the largest power of two dividing
# both sides that leaves the longer side at least 96 px. A refused spec is digested by its message.
"$cli" stability 2>/dev/null | awk -F' [|] ' 'NR > 2 && $2 ~ /x/ { sub(/^[|] /, "", $1); print $1 "|" $2 }' >cases.txt
awk -F'|' '{ split($2, s, "x"); if (s[1] > 1 && s[2] > 1 && (!($1 in best) || s[1] * s[2] < area[$1])) { best[$1] = $2; area[$1] = s[1] * s[2] } }
  END { for (k in best) print k "|" best[k] }' cases.txt | LC_ALL=C sort >specs.txt
rm cases.txt
n=0
while IFS='|' read -r spec size; do
  w=${size%x*} h=${size#*x} n=$((n + 1))
  while (( w % 2 == 0 && h % 2 == 0 && (w > h ? w : h) / 2 >= 96 )); do w=$((w / 2)) h=$((h / 2)); done
  echo "$spec ${w}x$h" >>case_specs.txt
  run convert src.png --to "$spec" --size "${w}x$h" --yaw 160 --pitch 5 case_to_$n.png 2>case_to_$n.err || true
  [[ -s case_to_$n.err ]] || rm case_to_$n.err
  if [[ -f case_to_$n.png ]]; then
    run convert case_to_$n.png --from "$spec" --to equirect --size 128x64 --interp bilinear case_back_$n.png 2>case_back_$n.err || true
    [[ -s case_back_$n.err ]] || rm case_back_$n.err
  fi
done <specs.txt
rm specs.txt

# Kernels, antialiasing, engines.
for k in nearest bilinear bicubic lanczos3 bicubic-dering lanczos3-dering; do
  run convert src.png --to pinhole:hfov=70 --size 200x150 --yaw 30 --roll 5 --interp "$k" k_$k.png
  run convert to_16.png --from cubemap --to fisheye:fov=190 --size 200x200 --interp "$k" kc_$k.png
  run convert src.png --to hammer --size 160x80 --interp "$k" kh_$k.png
done
for a in auto off mip 3; do
  run convert src.png --to equirect --size 128x64 --antialias "$a" aa_$a.png
  run convert src.png --to pinhole:hfov=150 --size 120x90 --antialias "$a" aap_$a.png
  run convert fish.png --from fisheye:fov=210 --to cubemap --size 192x32 --antialias "$a" aaf_$a.png
done
for e in simd scalar reference; do
  run convert src.png --to fisheye:fov=180 --size 160x160 --pitch 40 --engine "$e" e_$e.png
done
run convert "$root/samples/images/mars_spirit_1024x512_rgba.png" --to pinhole:hfov=120 --size 160x120 --alpha alpha.png
run convert src.png --to fisheye:fov=150 --size 160x160 --fill 1,0.5,0 --alpha fill_alpha.png
run convert src.png --to aitoff --size 200x100 --fill '#ff8000' fill.png
run convert "$root/samples/images/blender_city_1024x512.exr" --to cubemap --size 288x48 --depth float float.exr
run convert src.png --to cylindrical --size 200x100 --depth uint16 u16.png
run convert fish.png --from "@$root/samples/lenses/fisheye_220_kannala_brandt.yaml" --to equirect --size 256x128 lens.png
"$cli" maps --from equirect --source-size 512x256 --to pinhole:hfov=90 --size 64x48 --yaw 10 map_pinhole.tif >/dev/null
"$cli" maps --from cubemap --source-size 384x64 --to aitoff --size 128x64 map_aitoff.exr >/dev/null

# Tile pyramids and views: every file of their folders.
run tiles src.png tiles_p --tile 64 --preview 32 --yaw 10
run tiles src.png tiles_m --viewer marzipano --tile 32 --format png --interp bilinear --antialias mip
run tiles "$root/samples/images/mars_spirit_1024x512_rgba.png" tiles_a --tile 64 --format png --levels 2
run views src.png views_c --size 64x64
run views src.png views_r --rig ring:n=5,fov=80,pitch=-10 --layout folders --format png --size 48x40 --interp lanczos3
for d in tiles_p tiles_m tiles_a views_c views_r; do
  (cd $d && find . -type f | LC_ALL=C sort | while read -r f; do
    case $f in
      *.png | *.jpg) echo "$("$root/.venv/bin/python" -c 'import sys, hashlib, cv2; a = cv2.imread(sys.argv[1], cv2.IMREAD_UNCHANGED)
print(hashlib.sha256(str(a.shape).encode() + str(a.dtype).encode() + a.tobytes()).hexdigest())' "$f")  $f" ;;
      *) echo "$(sha256sum <"$f" | cut -d' ' -f1)  $f" ;;
    esac
  done) >$d.digests
  rm -rf $d
done

# Write options: depth, quality, chroma subsampling, metadata (JPEG bytes digested too).
jp="$root/samples/images/jordan_pond_4096x2048.jpg"
run convert "$jp" --to pinhole:hfov=80 --size 160x120 --quality 70 --subsampling 444 w_q70_444.jpg
run convert "$jp" --to pinhole:hfov=80 --size 160x120 --quality 100 --subsampling 422 w_q100_422.jpg
run convert "$jp" --to equirect --size 160x80 --no-metadata w_nometa.jpg
run convert "$jp" --to equirect --size 160x80 w_meta.jpg
run convert src.png --to fisheye:fov=200 --size 96x96 --depth half w_half.exr
run convert src.png --to fisheye:fov=200 --size 96x96 --depth uint16 w_u16.tif
for f in w_*.jpg; do cp "$f" "$f.bytes"; done

# PNG and JPEG: the decoded samples (OpenCV's reader, independent of panoproj's), so that encoder
# settings do not count; TIFF and OpenEXR: the bytes (their headers' write times masked).
py=$root/.venv/bin/python
for f in $(ls | LC_ALL=C sort); do
  case $f in
    *.digests) sed "s|  \./|  ${f%.digests}/|" "$f" ;;
    *.png | *.jpg)
      echo "$("$py" -c 'import sys, hashlib, cv2; a = cv2.imread(sys.argv[1], cv2.IMREAD_UNCHANGED)
print(hashlib.sha256(str(a.shape).encode() + str(a.dtype).encode() + a.tobytes()).hexdigest())' "$f")  $f" ;;
    *) echo "$(perl -0777 -pe 's/\d{4}:\d\d:\d\d \d\d:\d\d:\d\d/DATE/g' "$f" | sha256sum | cut -d' ' -f1)  $f" ;;
  esac
done
