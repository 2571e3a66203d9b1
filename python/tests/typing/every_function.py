"""Every public function and class of panoproj, called as users call them: mypy --strict and
pyright must find no error here (python/tests/test_typing.py)."""

from typing import Dict, List, Tuple

import numpy as np
import numpy.typing as npt

import panoproj as pp
from panoproj import compat

pano: npt.NDArray[np.uint8] = np.zeros((64, 128, 3), np.uint8)
a: npt.NDArray[np.generic] = pp.convert(pano, "equirect", pp.Pinhole(hfov=90.0), size=(32, 32), interp="bilinear",
                                        antialias="auto", engine="simd", yaw=1.0, pitch=2, roll=0.5, threads=1,
                                        alpha=True, fill=(1.0, 0.0, 0.0), memory_limit="1G")
b = pp.convert([pano[:, :64]] * 6, pp.Cubemap(layout="6x1"), "equirect", size="64x32", antialias=2)
sq = pano[:, :64]
c = pp.convert({"F": sq, "R": sq, "B": sq, "L": sq, "U": sq, "D": sq}, "cubemap", pp.Equirect())
fish = pp.Fisheye(fov=200, model="equisolid", clip="none", aspect="stretch", radius=10.0, cx=1.0, cy=1.0)
spec: pp.Projection = pp.projection("fisheye:fov=200")
print(str(fish), repr(spec), spec.params, spec == fish)
infos: List[pp.ProjectionInfo] = pp.projections()
print(infos[0].name, infos[0].parameters[0].key, infos[0].cls)
map_x, map_y = pp.build_map("equirect", "pinhole", (128, 64), size=(16, 16), convention="opencv")
grid: npt.NDArray[np.float32] = pp.build_map("equirect", "pinhole", (128, 64), convention="torch")
plan = pp.Plan("equirect", "cubemap", (128, 64), interp="nearest")
size: Tuple[int, int] = plan.size
out = plan.run(pano)
out2 = plan(pano)
img = pp.read("samples/images/jordan_pond_4096x2048.jpg")
img2, meta = pp.read("samples/images/jordan_pond_4096x2048.jpg", metadata=True)
info: Dict[str, object] = meta
pp.write("/tmp/panoproj-typing.png", img2, overwrite=True, quality=90, subsampling="444")
rays, ok = pp.to_ray("equirect", (128, 64), np.array([0.5]), np.array([0.5]), convention="panoproj")
x, y, hit = pp.to_pixel("equirect", (128, 64), rays, convention="torch")
faces: List[npt.NDArray[np.generic]] = pp.split_faces(out)
print(pp.simd_target(), pp.__version__)
report: Dict[str, object] = pp.tiles("samples/images/jordan_pond_4096x2048.jpg", "/tmp/panoproj-typing-tiles",
                                     viewer="marzipano", tile=256, levels=1, format="png", quality=90,
                                     script_url="js/", overwrite=True, interp="bilinear", yaw=10.0, threads=1)
cameras: Dict[str, object] = pp.views(["samples/images/jordan_pond_4096x2048.jpg"], "/tmp/panoproj-typing-views",
                                      rig=[{"name": "a", "yaw": 10.0, "hfov": 60, "size": (64, 48)}], format="png",
                                      quality=90, overwrite=True, size=(32, 32), interp="bilinear", threads=1)
dice = compat.e2c(pano, face_w=16, mode="bilinear", cube_format="dice")
listed = compat.e2c(pano, 16, cube_format="list")
named = compat.e2c(pano, 16, cube_format="dict")
back = compat.c2e(named, 32, 64, cube_format="dict", antialias="auto")
view = compat.e2p(pano, (90, 70), 10.0, 5.0, (24, 32), in_rot_deg=3, mode="bicubic")
cube_h = compat.cube_dice2h(dice)
print(compat.cube_h2dice(cube_h).shape, compat.cube_list2h(compat.cube_h2list(cube_h)).shape,
      compat.cube_dict2h(compat.cube_h2dict(cube_h)).shape, listed[0].shape, back.shape, view.shape)
