#!/usr/bin/env bash
# The main job: installs what is missing, builds, and converts the bundled real samples
# (samples/images) into every form panoproj writes. Results go to out/demo/ (or $1).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-"$root/out/demo"}
bash "$root/scripts/build.sh"
pp="$root/build/tools/panoproj"
img="$root/samples/images"
mkdir -p "$out"

pano="$img/jordan_pond_4096x2048.jpg"
earth="$img/xplanet_earth_2048x1024.jpg"
run() { "$pp" convert "$@" --overwrite; }

echo "== Jordan Pond equirect 4096x2048 into every form"
run "$pano" "$out/jordan_fisheye180.jpg" --to fisheye:fov=180
run "$pano" "$out/jordan_fisheye360.jpg" --to fisheye:fov=360 --size 2048x2048
run "$pano" "$out/jordan_fisheye180_down_equisolid.jpg" --to fisheye:fov=180,model=equisolid --pitch -90 --size 1536x1536
run "$pano" "$out/jordan_partial_equirect.jpg" --to equirect:hfov=180,vfov=90,lon0=60
run "$pano" "$out/jordan_cylindrical.jpg" --to cylindrical:vfov=100
run "$pano" "$out/jordan_pinhole.jpg" --to pinhole:hfov=90 --size 1920x1080 --yaw 75 --pitch -5
run "$pano" "$out/jordan_cubemap_cross.jpg" --to cubemap:layout=cross,face=1024
run "$pano" "$out/jordan_cube_{index}_{face}.jpg" --to cubemap:layout=files,face=1024
run "$pano" "$out/jordan_cubemap_eac.jpg" --to cubemap:layout=eac,face=1024
run "$pano" "$out/jordan_threejs_{axis}.jpg" --to cubemap:layout=files,preset=threejs,face=1024
run "$pano" "$out/jordan_aitoff.jpg" --to aitoff
run "$pano" "$out/jordan_eckert_greifendorff.jpg" --to eckert-greifendorff
run "$pano" "$out/jordan_bonne.jpg" --to bonne
run "$pano" "$out/jordan_mollweide.jpg" --to mollweide
run "$pano" "$out/jordan_panini.jpg" --to panini:hfov=150 --size 1920x1080 --yaw 75 --pitch -5
run "$pano" "$out/jordan_panini_opencv.jpg" --to panini:model=opencv,a=1.5,hfov=150 --size 1920x1080 --yaw 75 --pitch -5
run "$pano" "$out/jordan_compressed_rectilinear.jpg" --to compressed-rectilinear:hfov=150 --size 1920x1080 --yaw 75 --pitch -5
run "$pano" "$out/jordan_fisheye_thoby.jpg" --to fisheye:fov=185,model=thoby --pitch -90 --size 1536x1536

echo "== Earth (NASA Visible Earth) into the world maps"
run "$earth" "$out/earth_aitoff.jpg" --to aitoff
run "$earth" "$out/earth_eckert_greifendorff.jpg" --to eckert-greifendorff
run "$earth" "$out/earth_bonne.jpg" --to bonne:phi1=45
run "$earth" "$out/earth_hammer.jpg" --to hammer
run "$earth" "$out/earth_mollweide.jpg" --to mollweide
run "$earth" "$out/earth_sinusoidal.jpg" --to sinusoidal
run "$earth" "$out/earth_mercator.jpg" --to mercator
run "$earth" "$out/earth_transverse_mercator.jpg" --to transverse-mercator
run "$earth" "$out/earth_miller.jpg" --to miller
run "$earth" "$out/earth_gall_peters.jpg" --to cylindrical-equal-area:lat_ts=45

echo "== Stellarium 210-degree fisheye (looking at the zenith, South at the top) -> equirect"
# The lens looks up: pitch -90 levels the horizon; North (the image bottom) lands at the centre.
run "$img/stellarium_trees_fisheye210_512.png" "$out/trees_equirect.png" --from fisheye:fov=210 --to equirect --pitch -90

echo "== Calibrated lenses: a 220-degree Kannala-Brandt fisheye from a YAML file, a Double Sphere"
echo "   lens looking down, a Brown-Conrady camera with barrel distortion"
run "$pano" "$out/jordan_kannala_brandt220.jpg" --to @"$root/samples/lenses/fisheye_220_kannala_brandt.yaml" --size 1536x1536
run "$pano" "$out/jordan_double_sphere_down.jpg" --to double-sphere:xi=-0.18,alpha=0.59 --pitch -90 --size 1536x1536
run "$pano" "$out/jordan_brown_conrady_barrel.jpg" --to brown-conrady:fx=700,k1=-0.3,k2=0.08 --size 1920x1080 --yaw 75 --pitch -5
echo "== Calibration tools' files: a Kalibr omni-radtan camera, an OCamCalib fisheye; COLMAP's"
echo "   THIN_PRISM_FISHEYE to 220 degrees"
run "$pano" "$out/jordan_omni_radtan.jpg" --to "@$root/samples/lenses/kalibr_camchain.yaml#cam0" --size 1280x1024
run "$pano" "$out/jordan_ocamcalib.jpg" --to "@$root/samples/lenses/ocamcalib_fisheye190_calib_results.txt" --size 1024x768
run "$pano" "$out/jordan_thin_prism_fisheye.jpg" --to thin-prism-fisheye:fov=220,fx=260,k1=0.02,p1=0.002,sx1=0.004 --size 1024x1024

echo "== A 360 camera: two 200-degree lenses side by side, and back to equirect (blended across the"
echo "   20-degree overlap); a top/bottom pair whose back lens is turned a quarter"
run "$pano" "$out/jordan_dual_fisheye200.jpg" --to dual-fisheye:fov=200 --size 4096x2048
run "$out/jordan_dual_fisheye200.jpg" "$out/jordan_from_dual_fisheye.jpg" --from dual-fisheye:fov=200 --to equirect --size 4096x2048
run "$pano" "$out/jordan_dual_fisheye_top_bottom.jpg" --to dual-fisheye:fov=190,layout=top-bottom,roll2=90 --size 1024x2048

echo "== Stereo 360: a top-bottom frame (both eyes from the one mono panorama), then to YouTube's"
echo "   EAC side by side, each eye within its half"
run "$pano" "$out/jordan_stereo_tb.jpg" --to equirect:stereo=tb --size 2048x2048
run "$out/jordan_stereo_tb.jpg" "$out/jordan_stereo_eac_sbs.jpg" --from equirect:stereo=tb --to cubemap:layout=eac,stereo=sbs --size 3072x1024

echo "== Real cubemap (six files) -> equirect"
run "$img/cubemap_jordan_pond/face{index}_{face}.jpg" "$out/jordan_from_cubemap.jpg" --to equirect --size 4096x2048

echo "== Perspective views for SfM and NeRF: a ring of eight 90-degree views pitched 10 degrees up"
echo "   with COLMAP's model (one rig), rig_config.json and nerfstudio's transforms.json"
"$pp" views "$pano" "$out/jordan_views" --rig ring:n=8,fov=90,pitch=10 --size 960x720 --layout folders --overwrite

echo "== A COLMAP model's 220-degree fisheye (its image rendered through the model's own camera)"
echo "   undistorted into a rig of pinhole cube views with the new model (rigs, frames) and masks"
mkdir -p "$out/colmap_images"
run "$pano" "$out/colmap_images/jordan_fisheye220.jpg" --to "@$root/samples/colmap/fisheye220/cameras.txt#1" --pitch -20
"$pp" undistort "$root/samples/colmap/fisheye220" "$out/colmap_images" "$out/jordan_undistorted" --size 768x768 --overwrite

echo
echo "Results written to $out"
