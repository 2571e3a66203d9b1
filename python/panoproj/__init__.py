"""panoproj: convert images between projections (pinhole, fisheye, calibrated lenses, equirect,
cylindrical, cubemap, Aitoff, Hammer / Eckert-Greifendorff, Bonne) at native speed, from numpy.

Conventions (the same as the ``panoproj`` command; see docs/projections.md):

- Images are numpy arrays, ``HxW`` or ``HxWxC`` with C in 1..4, dtype uint8, uint16, float16 or
  float32. With 2 or 4 channels the last one is alpha. A C-contiguous array is read in place,
  never copied; any other layout is copied once to C order.
- A cubemap in memory is one image in its layout (6x1 by default: front, right, back, left, up,
  down); :func:`convert` also takes a list of six face arrays, and :func:`split_faces` gives
  the faces of a cubemap image as views.
- Sizes are ``(width, height)`` like OpenCV's ``dsize`` (or ``"WxH"``); angles in degrees.
- Pixel coordinates put pixel centres at ``i + 0.5`` (panoproj's convention); rays are unit
  vectors, x right, y down, z forward.
- Every heavy call releases the GIL. Errors, each with the command's one-line message:
  ``ValueError`` (bad parameters or shapes), ``TypeError`` (dtype, argument types), ``OSError``
  (files: ``FileNotFoundError`` for a missing input, ``FileExistsError`` for an existing output
  without ``overwrite=True``), ``MemoryError`` (a job over ``memory_limit``, by default the memory
  available now, refused before any work).
- Writes cannot lose data: a temporary file beside the target, synced, then renamed; on any error
  the old file is intact and nothing is left behind.
"""

from __future__ import annotations

import ast
import functools
import inspect
import re
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _core

__version__: str = _core.__version__  # the project's version (`panoproj --version` says the same)

# (the projection classes, one per catalogue name, are added below as they are made)
__all__ = [
    "Projection", "projection", "convert", "build_map", "Plan", "read", "write", "to_ray", "to_pixel", "split_faces",
    "simd_target",
]

SizeLike = Union[Tuple[int, int], str, None]


class Projection:
    """A projection spec: a name and parameters, as in ``"fisheye:fov=180,model=equisolid"``.

    Build one from keywords with the subclass (``Fisheye(fov=180, model="equisolid")``) or from
    spec text with :func:`projection`. Parameters not given take their defaults, some derived
    from the image size when the projection is used (``panoproj info`` lists them all).
    """

    name: str = ""
    _keys: Tuple[str, ...] = ()

    def __init__(self, **params: Any) -> None:
        unknown = [k for k in params if k not in self._keys]
        if unknown:
            raise TypeError(f"{type(self).__name__}: unknown parameter {unknown[0]!r} "
                            f"(expected one of {', '.join(self._keys)})")
        parts = [f"{k}={_text(v)}" for k, v in params.items() if v is not None]
        self._text = _core.canonical(self.name + (":" + ",".join(parts) if parts else ""))

    @property
    def params(self) -> Dict[str, Union[float, str]]:
        """The parameters given (not the defaults), by name."""
        _, _, rest = self._text.partition(":")
        return {k: _value(v) for k, v in (p.split("=", 1) for p in rest.split(",") if p)}

    def __str__(self) -> str:
        return self._text

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self.params.items())
        return f"{type(self).__name__}({args})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Projection) and self._text == other._text

    def __hash__(self) -> int:
        return hash(self._text)

    def __reduce__(self):
        return (projection, (self._text,))


def _text(v: Any) -> str:
    if isinstance(v, bool):
        raise TypeError(f"parameter value {v!r}: expected a number or a name")
    if isinstance(v, float):
        return repr(v)  # shortest text that reads back to the same double
    return str(v)


def _value(text: str) -> Union[float, int, str]:
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def _class_name(spec_name: str) -> str:
    return "".join(part.capitalize() for part in spec_name.split("-"))


_CLASSES: Dict[str, type] = {}
for _def in _core.catalog():
    _doc = _def["summary"] + ".\n\nParameters (degrees, pixels):\n" + "\n".join(
        f"    {p['key']}: {p['help']}" + (f" (default {p['default']})" if p["default"] else "")
        for p in _def["params"])
    _CLASSES[_def["name"]] = type(_class_name(_def["name"]), (Projection,), {
        "name": _def["name"], "_keys": tuple(p["key"] for p in _def["params"]), "__doc__": _doc,
        "__module__": __name__})
    globals()[_class_name(_def["name"])] = _CLASSES[_def["name"]]
    __all__.append(_class_name(_def["name"]))
del _def, _doc


def projection(spec: Union[str, Projection]) -> Projection:
    """The projection of spec text (``"pinhole:hfov=90"``), as an instance of its class."""
    if isinstance(spec, Projection):
        return spec
    if not isinstance(spec, str):
        raise TypeError(f"projection: {spec!r} (expected spec text or a Projection)")
    text = _core.canonical(spec)
    cls = _CLASSES[text.partition(":")[0]]
    p = cls.__new__(cls)
    p._text = text
    return p


def _spec(p: Union[str, Projection, None]) -> Optional[str]:
    return None if p is None else str(projection(p))


_MAX_SIDE = 2**31 - 1


def _size(size: SizeLike) -> Optional[Tuple[int, int]]:
    if size is None:
        return None
    if isinstance(size, str):
        m = re.fullmatch(r"\s*(\d+)\s*x\s*(\d+)\s*", size)
        if not m:
            raise ValueError(f"size: {size!r} (expected WxH, e.g. 4096x2048)")
        w, h = int(m.group(1)), int(m.group(2))
    else:
        try:
            w, h = size
        except (TypeError, ValueError):
            raise TypeError(f"size: {size!r} (expected (width, height))") from None
        if not all(isinstance(v, (int, np.integer)) and not isinstance(v, bool) for v in (w, h)):
            raise TypeError(f"size: {size!r} (expected two integers, (width, height))")
        w, h = int(w), int(h)
    if not (1 <= w <= _MAX_SIDE and 1 <= h <= _MAX_SIDE):
        raise ValueError(f"size: {w}x{h} (expected 1 to {_MAX_SIDE} pixels a side)")
    return w, h


def _int(name: str, v: Any, lo: int, hi: int, expected: str) -> int:
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
        raise TypeError(f"{name}: {v!r} (expected an integer, {expected})")
    if not lo <= int(v) <= hi:
        raise ValueError(f"{name}: {int(v)} (expected {expected})")
    return int(v)


def _threads(threads: Any) -> int:
    return _int("threads", threads, 0, 1024, "0 for all cores, or 1 to 1024")


def _angle(name: str, v: Any) -> float:
    try:
        return float(v)
    except OverflowError:
        raise ValueError(f"{name}: {v!r} (expected a finite angle in degrees)") from None
    except (TypeError, ValueError):
        raise TypeError(f"{name}: {v!r} (expected a number of degrees)") from None


def _memory_limit(limit: Union[int, str, None]) -> int:
    """Bytes (or text such as "4G", "512M"); None: the memory available when a job starts."""
    if limit is None:
        return 0
    if isinstance(limit, str):
        return _core.parse_memory_limit(limit)
    return _int("memory_limit", limit, 10**6, 9 * 10**18, "at least 1000000 bytes, or text such as '4G'")


def _one_line_type_errors(fn):
    """pybind11 answers an argument of a type it cannot convert with a list of overloads: one
    line instead, naming the call."""
    @functools.wraps(fn)
    def call(*args, **kwargs):
        try:
            return fn(*args, **kwargs)
        except TypeError as e:
            if "incompatible function arguments" in str(e) or "incompatible constructor arguments" in str(e):
                raise TypeError(f"{fn.__qualname__}: an argument of the wrong type (see help(panoproj."
                                f"{fn.__qualname__}))") from None
            raise
    return call


def _antialias(antialias: Union[str, int, None]) -> Optional[str]:
    if antialias is None or isinstance(antialias, str):
        return antialias
    if isinstance(antialias, (int, np.integer)) and not isinstance(antialias, bool):
        return str(int(antialias))
    raise TypeError(f"antialias: {antialias!r} (expected 'auto', 'off', 'mip', a sub-pixel count or None)")


FillLike = Union[str, Sequence[float], None]


def _fill(fill: FillLike) -> Optional[str]:
    if fill is None or isinstance(fill, str):
        return fill
    try:
        values = [float(v) for v in fill]
    except (TypeError, ValueError):
        raise TypeError(f"fill: {fill!r} (expected 'R,G,B[,A]', '#rrggbb[aa]' or a sequence of 3 or 4 numbers)") from None
    return ",".join(repr(v) for v in values)


# The conversion options, declared once in C++ (lib/src/engine/options.cpp): each is a keyword of
# convert / build_map / Plan where the table says so, its value checked here by its type (a few
# by name, for their Python forms) and handed to the row's setter.
_OPTIONS = _core.options()


def _option_text(name: str, v: Any) -> str:
    if not isinstance(v, str):
        raise TypeError(f"{name}: {v!r} (expected text)")
    return v


def _integer(name: str, v: Any) -> int:
    return _int(name, v, -2**63, 2**63 - 1, "a 64-bit integer")


def _size_text(name: str, v: Any) -> Optional[str]:
    size = _size(v)
    return None if size is None else "%dx%d" % size


def _bytes_text(name: str, v: Any) -> Optional[str]:
    limit = _memory_limit(v)
    return str(limit) if limit else None


_BY_TYPE = {"angle": _angle, "integer": _integer, "flag": lambda name, v: bool(v), "text": _option_text}
# Options with Python forms of their own: (width, height) sizes, sub-pixel counts, colour tuples, byte counts.
_BY_NAME = {
    "size": _size_text,
    "threads": lambda name, v: _threads(v),
    "antialias": lambda name, v: _antialias(v),
    "fill": lambda name, v: _fill(v),
    "memory_limit": _bytes_text,
}
_CHECKS = {o["name"]: _BY_NAME.get(o["name"]) or _BY_TYPE[o["type"]] for o in _OPTIONS}


def _core_options(given: Dict[str, Any]) -> Dict[str, Any]:
    """Keyword options as the core takes them (table order; None: not given)."""
    out = {}
    for name, check in _CHECKS.items():
        if name in given:
            v = check(name, given[name])
            if v is not None:
                out[name] = v
    return out


def _takes_options(use: str):
    """Gives fn (whose last parameter is ``options``) the table's options for ``use`` as keyword-only
    arguments, with their defaults, in its signature and docstring."""
    rows = [o for o in _OPTIONS if use in o["use"]]
    names = [o["name"] for o in rows]

    def wrap(fn):
        sig = inspect.signature(fn)
        fixed = [p for p in sig.parameters.values() if p.name not in ("self", "options")]
        first = [p for p in sig.parameters.values() if p.name == "self"]
        own = {p.name for p in fixed}
        expected = ", ".join(names + [p.name for p in fixed if p.kind == p.KEYWORD_ONLY])

        @functools.wraps(fn)
        def call(*args, **kwargs):
            given = {k: kwargs.pop(k) for k in list(kwargs) if k in names}
            bad = [k for k in kwargs if k not in own]
            if bad:
                raise TypeError(f"{fn.__qualname__}: unknown option {bad[0]!r} (expected one of: {expected})")
            return fn(*args, options=given, **kwargs)

        keywords = [inspect.Parameter(o["name"], inspect.Parameter.KEYWORD_ONLY, default=ast.literal_eval(o["default"]))
                    for o in rows]
        call.__signature__ = sig.replace(parameters=first + fixed + keywords)
        call.__doc__ = (fn.__doc__ or "") + "\n    Options (the command's flags of the same names):\n" + "\n".join(
            f"      {o['name']} = {o['default']}: {o['help']}" for o in rows) + "\n"
        return call
    return wrap


@_one_line_type_errors
@_takes_options("convert")
def convert(image: Union[np.ndarray, Sequence[np.ndarray]], src: Union[str, Projection, None],
            dst: Union[str, Projection], options: Dict[str, Any]) -> np.ndarray:
    """Converts ``image`` from projection ``src`` to ``dst`` and returns the new image.

    ``src=None`` takes a 2:1 image as a full equirect (as the command does); a list of six
    arrays is a cubemap's faces. The result has the input's dtype and channels; pixels without a
    source are 0 (alpha 0). In Python, ``size`` is ``(width, height)`` (or ``"WxH"``),
    ``antialias`` may be a sub-pixel count ``N``, ``fill`` a tuple ``(r, g, b[, a])`` in unit range,
    and ``memory_limit`` a byte count or text such as ``"4G"``; a job over it raises MemoryError
    before any work.
    """
    return _core.convert(image, _spec(src), _spec(dst), _core_options(options))


@_one_line_type_errors
@_takes_options("maps")
def build_map(src: Union[str, Projection], dst: Union[str, Projection], source_size: SizeLike, *,
              convention: str = "opencv", options: Dict[str, Any]) -> Tuple[np.ndarray, np.ndarray]:
    """Source-coordinate maps ``(map_x, map_y)``, float32 arrays of the output's shape.

    With ``convention="opencv"`` (pixel centres at integers, -1 where no source) they go straight
    into ``cv2.remap(img, map_x, map_y, cv2.INTER_LINEAR)``; ``"panoproj"`` gives centres at
    i + 0.5 and NaN where no source. Within 1/256 px of the exact map; cv2.remap itself rounds
    positions to 1/32 px and cannot wrap seams, poles or cube edges.
    """
    return _core.build_map(_spec(src), _spec(dst), _size(source_size), convention, _core_options(options))


class Plan:
    """One conversion geometry for many images of one source size (batches, video frames).

    The first run builds and keeps the map of the tiles whose geometry is not computed in
    registers; later runs reuse it. ``plan(image)`` or ``plan.run(image, out=array)`` (writes
    into a C-contiguous array of the output's shape and dtype). Safe to call from several
    threads at once. Pickles as its parameters, so it can be sent to multiprocessing, Dask or
    Ray workers (each rebuilds its map on its first run). Takes convert's options.
    """

    __slots__ = ("_args", "_plan")

    @_one_line_type_errors
    @_takes_options("convert")
    def __init__(self, src: Union[str, Projection], dst: Union[str, Projection], source_size: SizeLike,
                 options: Dict[str, Any]) -> None:
        self._args = (_spec(src), _spec(dst), _size(source_size), _core_options(options))
        self._plan = _core.Plan(*self._args)

    @property
    def src(self) -> Projection:
        return projection(self._args[0])

    @property
    def dst(self) -> Projection:
        return projection(self._args[1])

    @property
    def source_size(self) -> Tuple[int, int]:
        return self._args[2]

    @property
    def size(self) -> Tuple[int, int]:
        """The output's (width, height)."""
        return tuple(self._plan.size)

    @_one_line_type_errors
    def run(self, image: Union[np.ndarray, Sequence[np.ndarray]],
            out: Optional[np.ndarray] = None) -> np.ndarray:
        """Converts ``image``; with ``out``, into that array (which must not share memory with
        ``image``: ValueError)."""
        return self._plan.run(image, out)

    __call__ = run

    def __getstate__(self):
        return self._args

    def __setstate__(self, args) -> None:
        self._args = tuple(args)
        self._plan = _core.Plan(*self._args)

    def __repr__(self) -> str:
        src, dst, source_size, options = self._args
        shown = "".join(f", {k}={v!r}" for k, v in options.items() if k != "size")
        return f"Plan({src!r}, {dst!r}, source_size={source_size}, size={self.size}{shown})"


@_one_line_type_errors
def read(path: str, *, metadata: bool = False, memory_limit: Union[int, str, None] = None):
    """Reads an image file (JPEG, PNG, TIFF, EXR or HDR, by its magic bytes) through OpenImageIO as an array of the
    file's sample type (other types become float32). A path with ``{face}`` or ``{index}`` reads
    six cube face files as one 6x1 cubemap. With ``metadata=True`` returns ``(array, dict)``, the
    dict holding the file's attributes by OpenImageIO's names (EXIF, XMP, ICC profile ...)."""
    path = str(path)
    limit = _memory_limit(memory_limit)
    array = _core.read_faces(path, limit) if re.search(r"\{(face|index)\}", path) else _core.read(path, limit)
    if metadata:
        return array, _core.read_metadata(path.replace("{face}", "front").replace("{index}", "0"))
    return array


@_one_line_type_errors
def write(path: str, array: np.ndarray, *, overwrite: bool = False, dtype: Optional[str] = None,
          metadata: Optional[Dict[str, Any]] = None, quality: int = 95, subsampling: str = "420") -> None:
    """Writes an array atomically (a temporary file, then a rename): the format follows the
    extension. An existing file is replaced only with ``overwrite=True``. ``dtype`` converts the
    samples first (e.g. ``"uint8"`` for a JPEG of a float image); ``metadata`` attributes are
    written where the format has a place for them. A path with ``{face}``/``{index}`` writes a
    6x1 cubemap (6N x N) as six files, all replaced or none. On any error (a full disk, no
    permission) the old file is intact and no temporary is left. JPEG: ``quality`` 1 to 100,
    ``subsampling`` of the chroma "420" (half width and height), "422" (half width) or "444"."""
    _core.write(str(path), array, bool(overwrite), dtype, dict(metadata or {}),
                _int("quality", quality, 1, 100, "1 to 100"), str(subsampling))


@_one_line_type_errors
def to_ray(proj: Union[str, Projection], size: SizeLike, x, y) -> Tuple[np.ndarray, np.ndarray]:
    """Unit rays through pixel positions (x, y) of ``proj`` at ``size``: ``(rays[..., 3], ok)``;
    where ``ok`` is False (outside the projection) the ray is NaN."""
    return _core.to_ray(_spec(proj), _size(size), x, y)


@_one_line_type_errors
def to_pixel(proj: Union[str, Projection], size: SizeLike,
             rays) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pixel positions of rays (``[..., 3]``, any length but 0) in ``proj`` at ``size``:
    ``(x, y, ok)``; NaN where ``ok`` is False (the ray has no pixel)."""
    return _core.to_pixel(_spec(proj), _size(size), rays)


@_one_line_type_errors
def split_faces(image: np.ndarray, layout: Union[str, Projection] = "cubemap") -> List[np.ndarray]:
    """The six faces (front, right, back, left, up, down) of a cubemap image, as views."""
    spec = _spec(layout)
    face, origins = _core.face_origins(spec, (image.shape[1], image.shape[0]))
    return [image[y:y + face, x:x + face] for x, y in origins]


def simd_target() -> str:
    """The SIMD instruction set the engine dispatches to on this machine (e.g. ``AVX3``)."""
    return _core.simd_target()
