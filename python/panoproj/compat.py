"""py360convert's API (version 1.0.4) on panoproj: ``e2c``, ``c2e``, ``e2p`` and the ``cube_*``
helpers with its argument names, defaults, cube formats and face orientations, so code written for
it runs by changing the import::

    from panoproj import compat as py360convert

Cube formats (py360convert's): ``"horizon"`` one (w, 6w) array, faces F R B L U D left to right;
``"dice"`` a (3w, 4w) cross, U above F, L F R B across, D below (panoproj's
``cubemap:layout=cross``); ``"list"`` six (w, w) arrays in that order; ``"dict"`` the same by
``"F" "R" "B" "L" "U" "D"``. ``mode``: ``"nearest"``, ``"bilinear"``/``"linear"``,
``"bicubic"``/``"cubic"`` (panoproj's Keys cubic, not py360convert's spline of order 3); its other
spline orders raise ValueError naming these.

Where the results differ, on purpose: pixel centres sit half a pixel inside each face's and the
panorama's edges (py360convert puts its first and last samples on the edges, stretching each face
by one pixel); shrinking averages the source pixels under each output pixel (panoproj's
``antialias="auto"``), where py360convert samples one point; ``c2e`` takes any width (py360convert
wants a multiple of 8). Measured against py360convert on the Jordan Pond panorama:
python/tests/test_compat.py.
"""

from __future__ import annotations

import numbers
from typing import Any, Dict, List, Literal, Optional, Sequence, Tuple, Union, overload

import numpy as np

from . import Pinhole, _arrays, _core, convert, split_faces
from ._types import Array

CubeFormat = Literal["horizon", "list", "dict", "dice"]
InterpolationMode = Literal["nearest", "linear", "bilinear", "bicubic", "cubic"]

__all__ = ["e2c", "c2e", "e2p", "cube_h2dice", "cube_dice2h", "cube_h2dict", "cube_dict2h", "cube_h2list",
           "cube_list2h"]

_MODES = {"nearest": "nearest", "linear": "bilinear", "bilinear": "bilinear", "bicubic": "bicubic", "cubic": "bicubic"}
_SPLINES = ("biquadratic", "quadratic", "quad", "biquartic", "quartic", "biquintic", "quintic")
_LAYOUTS = {"horizon": "cubemap:layout=6x1", "dice": "cubemap:layout=cross"}
_FACES = "FRBLUD"


def _interp(mode: str) -> str:
    if not isinstance(mode, str) or mode.lower() not in _MODES:
        spline = isinstance(mode, str) and mode.lower() in _SPLINES
        raise ValueError(f"mode: {mode!r} ({'a spline order panoproj does not have; ' if spline else ''}expected "
                         "'nearest', 'bilinear' (or 'linear') or 'bicubic' (or 'cubic'))")
    return _MODES[mode.lower()]


def _pixels(name: str, v: Any) -> int:
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Integral) or not 1 <= int(v) <= 2**31 - 1:
        raise (ValueError if isinstance(v, numbers.Integral) else TypeError)(
            f"{name}: {v!r} (expected a whole number of pixels, 1 to 2147483647)")
    return int(v)


def _pair(name: str, v: Any, expected: str) -> Tuple[Any, Any]:
    if isinstance(v, (str, bytes)) or np.ndim(v) != 1 or len(v) != 2:
        raise (ValueError if np.ndim(v) == 1 and not isinstance(v, (str, bytes)) else TypeError)(
            f"{name}: {v!r} (expected {expected})")
    return v[0], v[1]


def _format(cube_format: str) -> str:
    if cube_format not in ("horizon", "list", "dict", "dice"):
        raise ValueError(f"cube_format: {cube_format!r} (expected 'horizon', 'list', 'dict' or 'dice')")
    return cube_format


@overload
def e2c(e_img: Any, face_w: int = ..., mode: InterpolationMode = ...,
        cube_format: Literal["horizon", "dice"] = ...) -> Array: ...
@overload
def e2c(e_img: Any, face_w: int = ..., mode: InterpolationMode = ..., *,
        cube_format: Literal["list"]) -> List[Array]: ...
@overload
def e2c(e_img: Any, face_w: int = ..., mode: InterpolationMode = ..., *,
        cube_format: Literal["dict"]) -> Dict[str, Array]: ...


def e2c(e_img: Any, face_w: int = 256, mode: InterpolationMode = "bilinear",
        cube_format: CubeFormat = "dice") -> Union[Array, List[Array], Dict[str, Array]]:
    """An equirectangular image (H, W[, C]) as a cubemap of ``face_w``-pixel faces in ``cube_format``."""
    fmt, interp, face_w = _format(cube_format), _interp(mode), _pixels("face_w", face_w)
    layout = _LAYOUTS.get(fmt, _LAYOUTS["horizon"])
    cols, rows = (4, 3) if fmt == "dice" else (6, 1)
    cube = convert(e_img, "equirect", layout, size=(cols * face_w, rows * face_w), interp=interp)  # type: ignore
    if fmt == "list":
        return cube_h2list(cube)
    if fmt == "dict":
        return cube_h2dict(cube)
    return cube


def c2e(cubemap: Any, h: int, w: int, mode: InterpolationMode = "bilinear",
        cube_format: CubeFormat = "dice") -> Array:
    """A cubemap in ``cube_format`` as an (h, w[, C]) equirectangular image."""
    fmt, interp, h, w = _format(cube_format), _interp(mode), _pixels("h", h), _pixels("w", w)
    if fmt == "list":
        if not isinstance(cubemap, (list, tuple)):
            raise TypeError(f"cubemap: {type(cubemap).__name__} (expected a list of six faces for cube_format='list')")
        source: Any = list(cubemap)
    elif fmt == "dict":
        if not isinstance(cubemap, dict):
            raise TypeError(f"cubemap: {type(cubemap).__name__} (expected a dict of F R B L U D for cube_format='dict')")
        source = cubemap
    else:
        source = _arrays.as_array(cubemap, "cubemap")
    return convert(source, _LAYOUTS.get(fmt, "cubemap"), "equirect", size=(w, h), interp=interp)  # type: ignore


def e2p(e_img: Any, fov_deg: Union[float, Tuple[float, float]], u_deg: float, v_deg: float,
        out_hw: Tuple[int, int], in_rot_deg: float = 0, mode: InterpolationMode = "bilinear") -> Array:
    """A perspective view of an equirectangular image: ``fov_deg`` (or (h_fov, v_fov)) degrees,
    looking ``u_deg`` right and ``v_deg`` up, turned ``in_rot_deg`` in the image plane, of
    ``out_hw`` = (height, width) pixels."""
    hfov, vfov = (fov_deg, fov_deg) if np.ndim(fov_deg) == 0 else _pair("fov_deg", fov_deg, "degrees, or (h_fov, v_fov)")
    out_h, out_w = _pair("out_hw", out_hw, "(height, width) in pixels")
    out_h, out_w = _pixels("out_hw height", out_h), _pixels("out_hw width", out_w)
    return convert(e_img, "equirect", Pinhole(hfov=float(hfov), vfov=float(vfov)), size=(out_w, out_h),
                   yaw=float(u_deg), pitch=float(v_deg), roll=float(in_rot_deg), interp=_interp(mode))  # type: ignore


def _faces(a: Any, layout: str, what: str) -> List[Array]:
    a = _arrays.as_array(a, what)
    cols, rows = (6, 1) if layout == "horizon" else (4, 3)
    if a.ndim not in (2, 3) or a.shape[0] * cols != a.shape[1] * rows:
        raise ValueError(f"{what}: shape {a.shape} (expected {rows if rows > 1 else ''}w x {cols}w pixels, w the face size, for "
                         f"cube_format='{layout}')")
    return split_faces(a, _LAYOUTS[layout])


def cube_h2list(cube_h: Any) -> List[Array]:
    """A horizon cubemap's six faces F R B L U D (views)."""
    return _faces(cube_h, "horizon", "cube_h")


def cube_list2h(cube_list: Sequence[Any]) -> Array:
    """Six faces side by side as a horizon cubemap."""
    faces = [_arrays.as_array(f, "face") for f in cube_list]
    if len(faces) != 6:
        raise ValueError(f"cube_list: {len(faces)} faces (expected 6: F R B L U D)")
    for k, f in zip(_FACES, faces):
        if f.shape != faces[0].shape or f.dtype != faces[0].dtype or f.ndim not in (2, 3) or f.shape[0] != f.shape[1]:
            raise ValueError(f"cube_list: face {k} is {f.shape} {f.dtype} (expected six square faces of the F face's "
                             f"{faces[0].shape} {faces[0].dtype})")
    return np.concatenate(faces, axis=1)


def cube_h2dict(cube_h: Any) -> Dict[str, Array]:
    """A horizon cubemap's faces by "F" "R" "B" "L" "U" "D"."""
    return dict(zip(_FACES, cube_h2list(cube_h)))


def cube_dict2h(cube_dict: Dict[Any, Any], face_k: Optional[Sequence[Any]] = None) -> Array:
    """Faces by key (``face_k``: the keys of F R B L U D, default "FRBLUD") as a horizon cubemap."""
    keys = list(face_k or _FACES)
    if len(keys) != 6:
        raise ValueError(f"face_k: {len(keys)} keys (expected 6, the keys of F R B L U D)")
    missing = [k for k in keys if k not in cube_dict]
    if missing:
        raise KeyError(f"cube_dict: no face {missing[0]!r} (expected keys {', '.join(map(str, keys))})")
    return cube_list2h([cube_dict[k] for k in keys])


def cube_h2dice(cube_h: Any) -> Array:
    """A horizon cubemap as a dice (3w x 4w; the six empty cells 0)."""
    faces = cube_h2list(cube_h)
    w = faces[0].shape[0]
    dice = np.zeros((3 * w, 4 * w) + faces[0].shape[2:], faces[0].dtype)
    _, origins = _core.face_origins(_LAYOUTS["dice"], (4 * w, 3 * w))
    for (x, y), face in zip(origins, faces):
        dice[y:y + w, x:x + w] = face
    return dice


def cube_dice2h(cube_dice: Any) -> Array:
    """A dice cubemap as a horizon cubemap."""
    return cube_list2h(_faces(cube_dice, "dice", "cube_dice"))
