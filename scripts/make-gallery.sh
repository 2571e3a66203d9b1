#!/usr/bin/env bash
# Regenerates the gallery's pictures (docs/gallery/*.jpg, shown by README.md and docs/gallery.md)
# from the main job's results: runs scripts/demo.sh, then makes small thumbnails with Pillow's
# area-aware resize (a docs-only tool in the project's .venv; panoproj itself does not depend on it).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/demo.sh" "$root/out/demo" >/dev/null
bash "$root/scripts/python-env.sh"
"$root/.venv/bin/python" -c "import PIL" 2>/dev/null || "$root/.venv/bin/python" -m pip install -q pillow
mkdir -p "$root/docs/gallery"
"$root/.venv/bin/python" - "$root/out/demo" "$root/docs/gallery" "$root/samples/images" <<'PY'
import sys, pathlib
from PIL import Image
src, dst, samples = map(pathlib.Path, sys.argv[1:4])
items = {
    "jordan_source.jpg": samples / "jordan_pond_4096x2048.jpg",
    "trees_source.jpg": samples / "stellarium_trees_fisheye210_512.png",
}
for name in ["jordan_fisheye180", "jordan_fisheye360", "jordan_fisheye180_down_equisolid",
             "jordan_partial_equirect", "jordan_cylindrical", "jordan_pinhole",
             "jordan_cubemap_cross", "jordan_aitoff", "jordan_eckert_greifendorff", "jordan_bonne",
             "earth_aitoff", "earth_eckert_greifendorff", "earth_bonne", "earth_hammer",
             "jordan_from_cubemap", "jordan_kannala_brandt220", "jordan_double_sphere_down",
             "jordan_brown_conrady_barrel", "jordan_omni_radtan", "jordan_ocamcalib", "jordan_thin_prism_fisheye",
             "jordan_dual_fisheye200", "jordan_from_dual_fisheye",
             "jordan_dual_fisheye_top_bottom", "jordan_mollweide", "jordan_panini", "jordan_panini_opencv",
             "jordan_compressed_rectilinear", "jordan_fisheye_thoby", "earth_mollweide", "earth_sinusoidal",
             "earth_mercator", "earth_transverse_mercator", "earth_miller", "earth_gall_peters",
             "jordan_cubemap_eac", "jordan_stereo_tb", "jordan_stereo_eac_sbs"]:
    items[name + ".jpg"] = src / (name + ".jpg")
items["trees_equirect.jpg"] = src / "trees_equirect.png"
for out, path in items.items():
    im = Image.open(path)
    if im.mode in ("RGBA", "LA"):  # transparent areas shown on white
        bg = Image.new("RGB", im.size, (255, 255, 255))
        bg.paste(im, mask=im.getchannel("A"))
        im = bg
    im = im.convert("RGB")
    im.thumbnail((320, 240), Image.LANCZOS)
    im.save(dst / out, quality=85, optimize=True)
print("gallery:", len(items), "thumbnails in", dst)
PY
# The views' picture: their borders where the written COLMAP cameras look (pycolmap), the views below.
"$root/.venv/bin/python" "$root/scripts/views_figure.py" "$root/out/demo/jordan_views" \
  "$root/samples/images/jordan_pond_4096x2048.jpg" "$root/docs/gallery/views_on_the_panorama.jpg"
# The undistorted fisheye: the 220-degree image and its views laid out as a cube's cross.
"$root/.venv/bin/python" - "$root/out/demo" "$root/docs/gallery/undistort_fisheye220.jpg" <<'PY'
import sys, pathlib
from PIL import Image
src, dst = pathlib.Path(sys.argv[1]), sys.argv[2]
fisheye = Image.open(src / "colmap_images" / "jordan_fisheye220.jpg").convert("RGB").resize((360, 360), Image.LANCZOS)
side = 120
figure = Image.new("RGB", (360 + 20 + 3 * side, 360), (255, 255, 255))
figure.paste(fisheye, (0, 0))
for view, (col, row) in {"up": (1, 0), "left": (0, 1), "front": (1, 1), "right": (2, 1), "down": (1, 2)}.items():
    face = Image.open(src / "jordan_undistorted" / "images" / view / "jordan_fisheye220.jpg").convert("RGB")
    figure.paste(face.resize((side, side), Image.LANCZOS), (380 + col * side, row * side))
figure.save(dst, quality=85, optimize=True)
print("gallery:", dst)
PY
