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

Sample positions are py360convert's, so the pictures agree (over 40 dB in every mode on the Jordan
Pond panorama: python/tests/test_compat.py): its grids put the first and last samples on the face,
view and panorama edges, and its ``c2e`` reads a face half a pixel past the exact position (panoproj
proper centres pixels exactly; these differ by up to half a pixel). Differences on purpose: faces are
chosen exactly where py360convert approximates their borders per column (so tiny outputs, a few
rows high, differ); ``c2e`` takes any width (py360convert wants a multiple of 8); keyword-only
``antialias="auto"`` averages the source pixels under each output pixel when shrinking, where
py360convert (and the default ``"off"``) samples one point.

Each call keeps what it builds (its plans, their maps, c2e's face masks) for the next call of the
same shapes and options, as py360convert caches its maps: the most recent (64 plans, 16 c2e
layouts), dropped by ``clear_cache()``.
"""

from __future__ import annotations

import functools
import math
import numbers
import threading
from typing import Any, Dict, List, Literal, Optional, Sequence, Tuple, Union, overload

import numpy as np

from . import Pinhole, Plan, _arrays, _core, split_faces, to_pixel, to_ray
from ._declared import Antialias
from ._text import shown as _shown
from ._types import Array

CubeFormat = Literal["horizon", "list", "dict", "dice"]
InterpolationMode = Literal["nearest", "linear", "bilinear", "bicubic", "cubic"]

__all__ = ["e2c", "c2e", "e2p", "clear_cache", "cube_h2dice", "cube_dice2h", "cube_h2dict", "cube_dict2h", "cube_h2list",
           "cube_list2h"]

_MODES = {"nearest": "nearest", "linear": "bilinear", "bilinear": "bilinear", "bicubic": "bicubic", "cubic": "bicubic"}
_SPLINES = ("biquadratic", "quadratic", "quad", "biquartic", "quartic", "biquintic", "quintic")
_LAYOUTS = {"horizon": "cubemap:layout=6x1", "dice": "cubemap:layout=cross"}
_FACES = "FRBLUD"


@functools.lru_cache(maxsize=64)  # (a c2e takes 20)
def _plan(src: str, dst: str, source_size: Tuple[int, int], size: Tuple[int, int], yaw: float, pitch: float,
          roll: float, interp: str, antialias: Any) -> Plan:
    """A plan kept for the next call of the same geometry (its maps built on its first run)."""
    return Plan(src, dst, source_size, size=size, yaw=yaw, pitch=pitch, roll=roll, interp=interp,  # type: ignore
                antialias=antialias)


def _convert(image: Array, src: str, dst: Any, *, size: Tuple[int, int], yaw: float = 0.0, pitch: float = 0.0,
             roll: float = 0.0, interp: str, antialias: Any = "off") -> Array:
    """convert() through a kept plan."""
    source_size = (image.shape[1], image.shape[0])
    return _plan(src, str(dst), source_size, size, yaw, pitch, roll, interp, antialias)(image)


_scratch = threading.local()  # this thread's last c2e: its key, padded faces and parts' buffers


def _antialias(antialias: Any) -> Any:
    """``antialias`` as a cache key (convert checks its value)."""
    try:
        hash(antialias)
    except TypeError:
        raise TypeError(f"antialias: {_shown(antialias)} (expected 'auto', 'off', 'mip' or a sub-pixel count)") from None
    return antialias


def clear_cache() -> None:
    """Drops the plans and masks kept for repeat calls (their memory)."""
    _plan.cache_clear()
    _c2e_layout.cache_clear()
    _ring_sources.cache_clear()
    _scratch.__dict__.clear()


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


# py360convert's sample grids (numpy.linspace) put the first and last samples on the edges: n pixels
# spanning tan(fov / 2) edge to edge are a pinhole of tan(fov' / 2) = tan(fov / 2) n / (n - 1), and
# n equirect columns span 360 n / (n - 1) degrees. Its c2e reads face coordinate t in [-1, 1] at pixel
# index (t + 1) w / 2, half a pixel past ours, from faces padded with their neighbours' pixels.
_ROTATIONS = ((0.0, 0.0), (90.0, 0.0), (180.0, 0.0), (-90.0, 0.0), (0.0, 90.0), (0.0, -90.0))  # F R B L U D
_POLE = 1e-6  # degrees: a pole row is a one-row strip this tall at the pole


def _edge_fov(fov: float, n: int) -> float:
    """The fov of an n-pixel pinhole whose first and last pixel centres lie on the edges of ``fov``."""
    return fov if n == 1 else math.degrees(2 * math.atan(math.tan(math.radians(fov) / 2) * n / (n - 1)))


def _fov(name: str, v: Any) -> float:
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Real) or not 0 < float(v) < 180:
        raise (ValueError if isinstance(v, numbers.Real) else TypeError)(
            f"{name}: {v!r} (expected degrees, 0 < fov < 180)")
    return float(v)


@overload
def e2c(e_img: Any, face_w: int = ..., mode: InterpolationMode = ...,
        cube_format: Literal["horizon", "dice"] = ..., *, antialias: Antialias = ...) -> Array: ...
@overload
def e2c(e_img: Any, face_w: int = ..., mode: InterpolationMode = ..., *,
        cube_format: Literal["list"], antialias: Antialias = ...) -> List[Array]: ...
@overload
def e2c(e_img: Any, face_w: int = ..., mode: InterpolationMode = ..., *,
        cube_format: Literal["dict"], antialias: Antialias = ...) -> Dict[str, Array]: ...


def e2c(e_img: Any, face_w: int = 256, mode: InterpolationMode = "bilinear",
        cube_format: CubeFormat = "dice", *, antialias: Antialias = "off") -> Union[Array, List[Array], Dict[str, Array]]:
    """An equirectangular image (H, W[, C]) as a cubemap of ``face_w``-pixel faces in ``cube_format``."""
    fmt, interp, face_w = _format(cube_format), _interp(mode), _pixels("face_w", face_w)
    antialias = _antialias(antialias)
    e_img = _arrays.as_array(e_img, "e_img")
    _core.require_memory(f"e2c cube 6 x {face_w}x{face_w}", 12 * face_w * face_w * e_img.itemsize *
                         (e_img.shape[2] if e_img.ndim == 3 else 1), 0)
    face = Pinhole(hfov=_edge_fov(90.0, face_w))
    faces = [_convert(e_img, "equirect", face, size=(face_w, face_w), yaw=yaw, pitch=pitch, interp=interp,
                      antialias=antialias) for yaw, pitch in _ROTATIONS]
    if fmt == "list":
        return faces
    if fmt == "dict":
        return dict(zip(_FACES, faces))
    return cube_h2dice(cube_list2h(faces)) if fmt == "dice" else cube_list2h(faces)


def _cube_faces(cubemap: Any, fmt: str) -> List[Array]:
    if fmt == "list":
        if not isinstance(cubemap, (list, tuple)):
            raise TypeError(f"cubemap: {type(cubemap).__name__} (expected a list of six faces for cube_format='list')")
        faces = [_arrays.as_array(f, "face") for f in cubemap]
    elif fmt == "dict":
        if not isinstance(cubemap, dict):
            raise TypeError(f"cubemap: {type(cubemap).__name__} (expected a dict of F R B L U D for cube_format='dict')")
        missing = [k for k in _FACES if k not in cubemap]
        if missing:
            raise KeyError(f"cubemap: no face {missing[0]!r} (expected keys F, R, B, L, U, D)")
        faces = [_arrays.as_array(cubemap[k], "face") for k in _FACES]
    else:
        faces = _faces(cubemap, fmt, "cubemap")
    _check_faces(faces, "cubemap")
    return faces


def _turn(yaw: float, pitch: float) -> Array:
    """rotation.hpp's R = Ry(yaw) Rx(pitch): a view's rays into the panorama's (x right, y up, z
    forward)."""
    a, b = math.radians(yaw), math.radians(pitch)
    ry = np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])
    rx = np.array([[1, 0, 0], [0, math.cos(b), -math.sin(b)], [0, math.sin(b), math.cos(b)]])
    return ry @ rx


@functools.lru_cache(maxsize=16)
def _ring_sources(w: int, pad: int) -> List[List[Tuple[int, Array, Array, Array]]]:
    """Per face, where each pixel of its ``pad``-wide ring comes from (nearest, from the cube's
    geometry): (face j, the ring pixels' flat indices in the padded face, their rows and columns in
    face j)."""
    n = w + 2 * pad
    ring = np.ones((n, n), bool)
    ring[pad:pad + w, pad:pad + w] = False
    where = np.flatnonzero(ring)
    rows, cols = np.divmod(where, n)
    frame = Pinhole(hfov=math.degrees(2 * math.atan(n / w)))
    rays, _ = to_ray(frame, (n, n), cols + 0.5, rows + 0.5)
    out = []
    for yaw, pitch in _ROTATIONS:
        x, y, _ = to_pixel("cubemap:layout=6x1", (6 * w, w), rays @ _turn(yaw, pitch).T)
        xs = np.clip(np.floor(x), 0, 6 * w - 1).astype(np.int64)
        ys = np.clip(np.floor(y), 0, w - 1).astype(np.int64)
        face = xs // w
        out.append([(int(j), where[face == j], ys[face == j], xs[face == j] - j * w) for j in np.unique(face)])
    return out


def _padded(faces: List[Array], pad: int, kept: Optional[List[Array]] = None) -> List[Array]:
    """Each face with ``pad`` pixels of its neighbours around it (nearest, from the cube's geometry),
    into ``kept`` (arrays of that shape) where given."""
    w = faces[0].shape[0]
    n = w + 2 * pad
    out = []
    strip = _strip_of(faces)  # (a horizon cube's faces: one gather from it, 10x faster)
    for i, (face, ring) in enumerate(zip(faces, _ring_sources(w, pad))):
        p = kept[i] if kept else np.empty((n, n) + face.shape[2:], face.dtype)
        p[pad:pad + w, pad:pad + w] = face
        flat = p.reshape((n * n,) + face.shape[2:])
        for j, where, ys, xs in ring:
            flat[where] = strip.take(ys * 6 * w + xs + j * w, axis=0) if strip is not None else faces[j][ys, xs]
        out.append(p)
    return out


def _strip_of(faces: List[Array]) -> Optional[Array]:
    """The C-contiguous (w, 6w[, C]) array the faces are consecutive column blocks of, flattened to
    (6 w^2[, C]); None if they are not."""
    base = faces[0].base
    w = faces[0].shape[0]
    if not isinstance(base, np.ndarray) or not base.flags.c_contiguous or base.shape[:2] != (w, 6 * w) or \
            base.shape[2:] != faces[0].shape[2:] or base.dtype != faces[0].dtype:
        return None
    start = base.__array_interface__["data"][0]
    step = w * base.itemsize * (base.shape[2] if base.ndim == 3 else 1)
    if any(f.base is not base or f.__array_interface__["data"][0] != start + j * step for j, f in enumerate(faces)):
        return None
    return base.reshape((6 * w * w,) + base.shape[2:])


def _pieces(h: int, w: int) -> List[Tuple[int, int, int, int]]:
    """(r0, r1, c0, c1) blocks of the h x w grid that are partial equirects: the pole rows alone (a
    strip at the pole), the columns in two halves (each spanning at most 360 degrees)."""
    rows = [(0, 1), (1, h - 1), (h - 1, h)] if h > 2 else [(i, i + 1) for i in range(h)]
    cols = [(0, w // 2), (w // 2, w)] if w > 1 else [(0, 1)]
    return [(r0, r1, c0, c1) for r0, r1 in rows if r1 > r0 for c0, c1 in cols]


@functools.lru_cache(maxsize=16)
def _c2e_layout(fw: int, h: int, w: int, antialias: Any) -> Tuple[int, List[Tuple[int, int, int, int, int, str, Any]]]:
    """c2e's padding and its pieces: (a0, a1, b0, b1) output box, face, the partial equirect it
    takes from that face, and the box's mask of the samples on that face as row runs."""
    # The faces' pixels reach past their edges by up to an output pixel's footprint (antialiasing):
    # padding wider than it keeps every footprint inside the padded face.
    pad = min(fw, 2 + math.ceil(2 * fw / max(1, min(w // 4, h // 2))))
    lon = np.radians(np.linspace(-180.0, 180.0, w))
    lat = np.radians(np.linspace(90.0, -90.0, h))
    # Each sample's face: the ray's largest component (x right, y up, z forward).
    band = np.where(np.abs(np.cos(lon)) >= np.abs(np.sin(lon)), np.where(np.cos(lon) > 0, 0, 2),
                    np.where(np.sin(lon) > 0, 1, 3)).astype(np.int8)
    polar = np.abs(np.tan(lat))[:, None] >= np.maximum(np.abs(np.sin(lon)), np.abs(np.cos(lon)))[None, :]
    face_of = np.where(polar, np.where(lat > 0, 4, 5).astype(np.int8)[:, None], band[None, :])
    dlon, dlat = 360.0 / max(1, w - 1), 180.0 / max(1, h - 1)
    pieces = []
    for r0, r1, c0, c1 in _pieces(h, w):
        piece = face_of[r0:r1, c0:c1]
        for k in np.nonzero(np.bincount(piece.ravel(), minlength=6))[0]:  # each face over its box in this piece
            mask = piece == k
            rows, cols = np.nonzero(mask.any(1))[0], np.nonzero(mask.any(0))[0]
            a0, a1, b0, b1 = int(r0 + rows[0]), int(r0 + rows[-1] + 1), int(c0 + cols[0]), int(c0 + cols[-1] + 1)
            lat0, lon0 = 90.0 - (a0 + (a1 - a0 - 1) / 2) * dlat, -180.0 + (b0 + (b1 - b0 - 1) / 2) * dlon
            vfov = (a1 - a0) * dlat if abs(lat0) < 90 else _POLE
            hfov = (b1 - b0) * dlon if w > 1 else _POLE
            lat0 = max(vfov / 2 - 90, min(90 - vfov / 2, lat0))
            target = f"equirect:hfov={hfov!r},vfov={vfov!r},lon0={lon0!r},lat0={lat0!r}"
            pieces.append((a0, a1, b0, b1, int(k), target, _row_runs(mask[a0 - r0:a1 - r0, b0 - c0:b1 - c0])))
    return pad, pieces


def _row_runs(mask: Array) -> List[Tuple[int, int, Optional[Array]]]:
    """A mask as runs of rows: (first, end, None) where every sample is set (copied whole),
    (first, end, mask rows) where not."""
    full = np.asarray(mask.all(1), bool)
    edges = np.flatnonzero(np.diff(full.astype(np.int8))) + 1
    bounds = [0, *edges.tolist(), len(full)]
    return [(a, b, None if full[a] else mask[a:b].copy()) for a, b in zip(bounds, bounds[1:])]


def c2e(cubemap: Any, h: int, w: int, mode: InterpolationMode = "bilinear",
        cube_format: CubeFormat = "dice", *, antialias: Antialias = "off") -> Array:
    """A cubemap in ``cube_format`` as an (h, w[, C]) equirectangular image."""
    fmt, interp, h, w = _format(cube_format), _interp(mode), _pixels("h", h), _pixels("w", w)
    antialias = _antialias(antialias)
    faces = _cube_faces(cubemap, fmt)
    fw = faces[0].shape[0]
    _core.require_memory(f"c2e output {w}x{h}", h * w * (faces[0][0, 0].nbytes + 3), 0)
    pad, pieces = _c2e_layout(fw, h, w, antialias)
    # The padded faces and the parts go into buffers this thread keeps for its next c2e of the
    # same kind.
    key = (fw, h, w, interp, antialias, faces[0].dtype, faces[0].shape[2:])
    if getattr(_scratch, "key", None) != key:
        _scratch.key, _scratch.parts, _scratch.padded = key, [None] * len(pieces), None
    padded = _scratch.padded = _padded(faces, pad, _scratch.padded)
    out = np.empty((h, w) + faces[0].shape[2:], faces[0].dtype)  # (the pieces' masks cover it)
    source = Pinhole(focal=fw / 2, cx=fw / 2 + pad, cy=fw / 2 + pad)  # py360convert's index (t + 1) w / 2
    parts = _scratch.parts
    for i, (a0, a1, b0, b1, k, target, runs) in enumerate(pieces):
        yaw, pitch = _ROTATIONS[k]
        plan = _plan(str(source), target, (fw + 2 * pad, fw + 2 * pad), (b1 - b0, a1 - a0), -yaw, -pitch, 0.0, interp,
                     antialias)
        as_is = parts[i] is not None and out.ndim == 3 and out.shape[2] <= 4
        part = plan.run(padded[k], out=parts[i]) if as_is else plan(padded[k])
        parts[i] = part
        for first, end, mask in runs:
            if mask is None:
                out[a0 + first:a0 + end, b0:b1] = part[first:end]
            else:
                _paste(out[a0 + first:a0 + end, b0:b1], part[first:end], mask)
    return out


def _paste(dst: Array, src: Array, where: Array) -> None:
    """dst[where] = src[where], a pixel at a time (channels as one opaque item: 40x faster than a
    broadcast mask)."""
    if dst.ndim == 3:
        item = np.dtype((np.void, dst.shape[2] * dst.itemsize))
        dst, src = dst.view(item)[..., 0], np.ascontiguousarray(src).view(item)[..., 0]
    np.copyto(dst, src, where=where)


def e2p(e_img: Any, fov_deg: Union[float, Tuple[float, float]], u_deg: float, v_deg: float,
        out_hw: Tuple[int, int], in_rot_deg: float = 0, mode: InterpolationMode = "bilinear", *,
        antialias: Antialias = "off") -> Array:
    """A perspective view of an equirectangular image: ``fov_deg`` (or (h_fov, v_fov)) degrees,
    looking ``u_deg`` right and ``v_deg`` up, turned ``in_rot_deg`` in the image plane, of
    ``out_hw`` = (height, width) pixels."""
    hfov, vfov = (fov_deg, fov_deg) if np.ndim(fov_deg) == 0 else _pair("fov_deg", fov_deg, "degrees, or (h_fov, v_fov)")
    hfov, vfov = _fov("fov_deg", hfov), _fov("fov_deg", vfov)
    out_h, out_w = _pair("out_hw", out_hw, "(height, width) in pixels")
    out_h, out_w = _pixels("out_hw height", out_h), _pixels("out_hw width", out_w)
    view = Pinhole(hfov=_edge_fov(hfov, out_w), vfov=_edge_fov(vfov, out_h))
    antialias = _antialias(antialias)
    return _convert(_arrays.as_array(e_img, "e_img"), "equirect", view, size=(out_w, out_h), yaw=float(u_deg),
                    pitch=float(v_deg), roll=float(in_rot_deg), interp=_interp(mode), antialias=antialias)


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


def _check_faces(faces: List[Array], what: str) -> None:
    if len(faces) != 6:
        raise ValueError(f"{what}: {len(faces)} faces (expected 6: F R B L U D)")
    for k, f in zip(_FACES, faces):
        if f.shape != faces[0].shape or f.dtype != faces[0].dtype or f.ndim not in (2, 3) or f.shape[0] != f.shape[1]:
            raise ValueError(f"{what}: face {k} is {f.shape} {f.dtype} (expected six square faces of the F face's "
                             f"{faces[0].shape} {faces[0].dtype})")


def cube_list2h(cube_list: Sequence[Any]) -> Array:
    """Six faces side by side as a horizon cubemap."""
    faces = [_arrays.as_array(f, "face") for f in cube_list]
    _check_faces(faces, "cube_list")
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
    for (x, y, _), face in zip(origins, faces):
        dice[y:y + w, x:x + w] = face
    return dice


def cube_dice2h(cube_dice: Any) -> Array:
    """A dice cubemap as a horizon cubemap."""
    return cube_list2h(_faces(cube_dice, "dice", "cube_dice"))
