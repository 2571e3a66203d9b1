"""panoproj: convert images between projections (pinhole, fisheye, calibrated lenses, equirect,
cylindrical, cubemap, Aitoff, Hammer / Eckert-Greifendorff, Bonne) at native speed, from numpy.

Conventions (the same as the ``panoproj`` command; see docs/projections.md):

- Images are arrays ``HxW``, ``HxWxC`` or batches ``NxHxWxC`` of any channel count (2 or 4:
  alpha last; more than 4 in groups, no alpha): uint8, uint16, float16, float32 as they are,
  float64 through float32, any integer/bool/float with ``interp="nearest"`` exactly; anything
  numpy reads (``__dlpack__``, ``__array__``, buffers). A C-contiguous array is read in place.
- A cubemap in memory is one image in its layout (6x1 by default: front, right, back, left, up,
  down); :func:`convert` also takes six face arrays (a list, or a dict by ``F R B L U D``), and
  :func:`split_faces` gives the faces of a cubemap image as views.
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
import difflib
import functools
import inspect
import os
import re
import warnings
from concurrent.futures import ThreadPoolExecutor
from typing import (TYPE_CHECKING, Any, Callable, Dict, List, Mapping, NamedTuple, Optional, Sequence, Tuple, TypeVar,
                    Union, cast, overload)

import numpy as np

from . import _arrays, _coordinates, _core, _declared, _tiles, _views
from ._declared import *  # noqa: F401,F403 (the projection classes and Literal aliases)
from ._declared import CLASSES, ConvertOptions, MapOptions, ProjectionName, TilesOptions, ViewsOptions
from ._projection import _CLASSES, Projection, projection
from ._types import Array, FillLike, ImageLike, Mask, PathLike, SizeLike

if TYPE_CHECKING:
    from typing import Literal

    from typing_extensions import Unpack

__version__: str = _core.__version__  # the project's version (`panoproj --version` says the same)

_CLASSES.update(CLASSES)
__all__ = [
    "Projection", "projection", "projections", "ProjectionInfo", "ParameterInfo", "convert", "build_map", "Plan",
    "read", "write", "to_ray", "to_pixel", "split_faces", "simd_target", "tiles", "views", "ConvertOptions", "MapOptions",
    "TilesOptions", "ViewsOptions",
    "SizeLike", "FillLike", "ImageLike", "PathLike",
]
__all__ += _declared.__all__  # the projection classes and the Literal aliases


class ParameterInfo(NamedTuple):
    """One key of a projection: ``kind`` is "number", "integer", "choice" or "text"; ``default`` is text
    ("" when derived from the image); ``lo``/``hi`` bound numbers; ``choices`` are a choice's names."""

    key: str
    kind: str
    default: str
    lo: float
    hi: float
    choices: Tuple[str, ...]
    help: str


class ProjectionInfo(NamedTuple):
    """A catalogue entry: its spec name, its class, a one-line summary and its keys."""

    name: str
    cls: type
    summary: str
    parameters: Tuple[ParameterInfo, ...]


def projections() -> List[ProjectionInfo]:
    """The catalogue: every projection panoproj converts from and to (``panoproj info`` lists the same)."""
    return [ProjectionInfo(d["name"], CLASSES[d["name"]], d["summary"], tuple(
        ParameterInfo(p["key"], p["type"], p["default"], p["lo"], p["hi"],
                      tuple(p["choices"].split("|")) if p["choices"] else (), p["help"]) for p in d["params"]))
        for d in _core.catalog()]


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


_F = TypeVar("_F", bound=Callable[..., Any])


def _one_line_type_errors(fn: _F) -> _F:
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
    return cast(_F, call)


def _antialias(antialias: Union[str, int, None]) -> Optional[str]:
    if antialias is None or isinstance(antialias, str):
        return antialias
    if isinstance(antialias, (int, np.integer)) and not isinstance(antialias, bool):
        return str(int(antialias))
    raise TypeError(f"antialias: {antialias!r} (expected 'auto', 'off', 'mip', a sub-pixel count or None)")




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
_CHOICES = {o["name"]: o["choices"].split("|") for o in _OPTIONS if o["choices"]}


def _option_text(name: str, v: Any) -> str:
    if not isinstance(v, str):
        raise TypeError(f"{name}: {v!r} (expected text)")
    choices = _CHOICES.get(name)
    if choices and v not in choices:
        near = difflib.get_close_matches(v, choices, 1)
        raise ValueError(f"{name}: {v!r} (expected one of {', '.join(choices)}"
                         + (f"; did you mean {near[0]!r}?)" if near else ")"))
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


def _takes_options(use: str) -> Callable[[_F], _F]:
    """Gives fn (declared with ``**options``) the table's options for ``use`` as keyword-only
    arguments, with their defaults, in its runtime signature and docstring; unknown keywords
    raise TypeError naming the ones it takes."""
    rows = [o for o in _OPTIONS if use in o["use"]]
    names = [o["name"] for o in rows]

    def wrap(fn: _F) -> _F:
        sig = inspect.signature(fn)
        fixed = [p for p in sig.parameters.values() if p.kind != p.VAR_KEYWORD]
        own = {p.name for p in fixed}
        expected = ", ".join(names + [p.name for p in fixed if p.kind == p.KEYWORD_ONLY])

        @functools.wraps(fn)
        def call(*args, **kwargs):
            bad = [k for k in kwargs if k not in own and k not in names]
            if bad:
                near = difflib.get_close_matches(bad[0], names + list(own), 1)
                raise TypeError(f"{fn.__qualname__}: unknown option {bad[0]!r} ("
                                + (f"did you mean {near[0]!r}? " if near else "") + f"expected one of: {expected})")
            return fn(*args, **kwargs)

        keywords = [inspect.Parameter(o["name"], inspect.Parameter.KEYWORD_ONLY, default=ast.literal_eval(o["default"]))
                    for o in rows]
        call.__signature__ = sig.replace(parameters=fixed + keywords)  # type: ignore[attr-defined]
        call.__doc__ = (fn.__doc__ or "") + "\n    Options (the command's flags of the same names):\n" + "\n".join(
            f"      {o['name']} = {o['default']}: {o['help']}" for o in rows) + "\n"
        return cast(_F, call)
    return wrap


def _source_spec(src: Union[str, Projection, None], size: Optional[Tuple[int, int]]) -> str:
    """src=None takes a 2:1 image as a full equirect, as the command does."""
    if src is not None:
        return str(projection(src))
    if size is None:
        return "cubemap"
    if size[0] != 2 * size[1]:
        raise ValueError(f"src: None, and a {size[0]}x{size[1]} image is not a 2:1 equirect (give src, e.g. "
                         "'fisheye:fov=180')")
    return "equirect"


def _check_target_size(dst: str, options: Dict[str, Any]) -> None:
    """A (height, width) given for an equirect or cylindrical target's (width, height) transposes it."""
    size = _size(options.get("size"))
    p = projection(dst)
    if size is None or p.name not in ("equirect", "cylindrical"):
        return
    hfov, vfov = float(p.params.get("hfov", 360)), float(p.params.get("vfov", 180 if p.name == "equirect" else 100))
    w, h = size
    if w != h and abs(h / w - hfov / vfov) < 1e-9 * hfov / vfov:
        warnings.warn(f"size=({w}, {h}) is (width, height): this {p.name} (hfov {hfov:g}, vfov {vfov:g}) would get "
                      f"pixels {(hfov / w) / (vfov / h):g}x as wide as tall in degrees; did you mean size=({h}, {w})?",
                      UserWarning, stacklevel=4)


def _image_job(image: Any) -> Tuple[Any, Optional[Tuple[int, int]]]:
    """A cubemap's faces (a list of arrays) or one array as numpy holds it, and its source (width, height)."""
    faces = _arrays.faces_of(image)
    if faces is not None:
        for f in faces:
            _arrays.check_layout(f, "cube face")
        return faces, None
    a = _arrays.as_array(image)
    _arrays.check_layout(a)
    return a, (a.shape[-2], a.shape[-3]) if a.ndim == 4 else (a.shape[1], a.shape[0])


def _codec(image: Any, options: Dict[str, Any]) -> "_arrays.Codec":
    first = image[0] if isinstance(image, list) else image
    codec = _arrays.codec_for(first, options.get("interp", "bicubic"))
    _arrays.refuse_alpha(codec, options)
    return codec


@_one_line_type_errors
@_takes_options("convert")
def convert(image: ImageLike, src: Union[str, Projection, None], dst: Union[str, Projection],
            **options: Unpack[ConvertOptions]) -> Array:
    """Converts ``image`` from projection ``src`` to ``dst`` and returns the new image.

    ``image``: HxW, HxWxC, a batch NxHxWxC (frames converted in parallel on one plan, equal to
    converting each), or a cubemap's six faces (a list, or a dict by ``F R B L U D``); numpy or
    anything numpy reads (``__array__``, ``__dlpack__``, buffers). The result has the input's
    dtype and channels (float64 computed in float32); pixels without a source are 0 (alpha 0).
    ``src=None`` takes a 2:1 image as a full equirect, as the command does. In Python, ``size``
    is ``(width, height)`` (or ``"WxH"``), ``antialias`` may be a sub-pixel count ``N``, ``fill`` a
    tuple ``(r, g, b[, a])`` in unit range, and ``memory_limit`` a byte count or text such as
    ``"4G"``; a job over it raises MemoryError before any work.
    """
    job, size = _image_job(image)
    src_spec, dst_spec = _source_spec(src, size), str(projection(dst))
    _check_target_size(dst_spec, options)
    codec = _codec(job, options)
    core = _core_options(options)
    if not isinstance(job, list) and job.ndim == 4:
        plan = _core.Plan(src_spec, dst_spec, size, {**core, "threads": 1})
        return _convert_batch(job, plan, codec, options)
    run = lambda im, alpha: _core.convert(im, src_spec, dst_spec, core, alpha)  # noqa: E731
    return _arrays.run_faces(job, codec, run) if isinstance(job, list) else _arrays.run_image(job, codec, run)


def _convert_batch(frames: Array, plan: Any, codec: "_arrays.Codec", options: Dict[str, Any]) -> Array:
    """Frames shared out to the threads, each converted on one thread by a one-thread plan (no
    per-frame sync), into one array sized (and checked against memory_limit) after the first."""
    run = lambda im, alpha: plan.run(im, None, alpha)  # noqa: E731
    first = _arrays.run_image(frames[0], codec, run)
    _core.require_memory(f"batch output {len(frames)} x {'x'.join(map(str, first.shape))}",
                         first.nbytes * len(frames), _memory_limit(options.get("memory_limit")))
    out = np.empty((len(frames),) + first.shape, first.dtype)
    out[0] = first

    def one(i: int) -> None:
        if codec.as_is:
            plan.run(frames[i], out[i], True)
        else:
            out[i] = _arrays.run_image(frames[i], codec, run)

    workers = _threads(options.get("threads", 0)) or os.cpu_count() or 1
    with ThreadPoolExecutor(max(1, min(workers, len(frames) - 1))) as pool:
        list(pool.map(one, range(1, len(frames))))
    return out


@overload
def build_map(src: Union[str, Projection], dst: Union[str, Projection], source_size: SizeLike, *,
              convention: Literal["opencv", "panoproj"] = ..., **options: Unpack[MapOptions]) -> Tuple[Array, Array]: ...
@overload
def build_map(src: Union[str, Projection], dst: Union[str, Projection], source_size: SizeLike, *,
              convention: Literal["torch"], **options: Unpack[MapOptions]) -> Array: ...


@_one_line_type_errors
@_takes_options("maps")
def build_map(src: Union[str, Projection], dst: Union[str, Projection], source_size: SizeLike, *,
              convention: _coordinates.Convention = "opencv",
              **options: Unpack[MapOptions]) -> Union[Tuple[Array, Array], Array]:
    """Source-coordinate maps of the output's shape.

    ``convention="opencv"`` (pixel centres at integers, -1 where no source): ``(map_x, map_y)``,
    float32, straight into ``cv2.remap(img, map_x, map_y, cv2.INTER_LINEAR)``; ``"panoproj"``:
    centres at i + 0.5 and NaN where no source; ``"torch"``: one (H, W, 2) float32 grid for
    ``torch.nn.functional.grid_sample(img, grid[None], align_corners=False)``, normalized to
    [-1, 1] across the source's edges, -2 where no source. Within 1/256 px of the exact map;
    cv2.remap itself rounds positions to 1/32 px and cannot wrap seams, poles or cube edges.
    """
    convention = _coordinates.check(convention)
    size = _source_size(source_size)
    _check_target_size(str(projection(dst)), options)
    maps = _core.build_map(str(projection(src)), str(projection(dst)), size,
                           "panoproj" if convention == "torch" else convention, _core_options(options))
    return _coordinates.torch_grid(*maps, size) if convention == "torch" else maps


def _source_size(size: SizeLike) -> Tuple[int, int]:
    if size is None:
        raise TypeError("source_size: None (expected the source image's (width, height), e.g. image.shape[1::-1])")
    out = _size(size)
    assert out is not None
    return out


class Plan:
    """One conversion geometry for many images of one source size (batches, video frames).

    The first run keeps, per tile, the map of a tile whose geometry is not computed in registers
    or the source taps and weights the others plan (at most 17 bytes an output pixel, counted
    against ``memory_limit``; outputs over ~30 Mpx keep nothing); later runs on images of the same
    dtype and channels reuse them and only gather, to the same bytes (uint8 bilinear: about a
    third of the first run's time). ``plan(image)`` or ``plan.run(image, out=array)`` (writes
    into a C-contiguous array of the output's shape and dtype). Takes what :func:`convert` takes
    (dtypes, channels, batches, faces). Safe to call from several threads at once. Pickles as
    its parameters, so it can be sent to multiprocessing, Dask or Ray workers (each rebuilds its
    map on its first run). Takes convert's options.
    """

    __slots__ = ("_args", "_plan", "_given", "_frame_plan")

    @_one_line_type_errors
    @_takes_options("convert")
    def __init__(self, src: Union[str, Projection], dst: Union[str, Projection], source_size: SizeLike,
                 **options: Unpack[ConvertOptions]) -> None:
        size = _source_size(source_size)
        _check_target_size(str(projection(dst)), options)
        self._given = dict(options)
        self._args = (str(projection(src)), str(projection(dst)), size, _core_options(options))
        self._plan = _core.Plan(*self._args)
        self._frame_plan: Any = None  # batches: a one-thread plan, each frame on its own thread

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
        w, h = self._plan.size
        return (w, h)

    @_one_line_type_errors
    def run(self, image: ImageLike, out: Optional[Array] = None) -> Array:
        """Converts ``image``; with ``out``, into that array (which must not share memory with
        ``image``: ValueError)."""
        job, _ = _image_job(image)
        codec = _codec(job, self._given)
        if not isinstance(job, list) and job.ndim == 4:
            if out is not None:
                raise ValueError("out: not with a batch (convert the frames one by one into out[i], or take the result)")
            if self._frame_plan is None:
                src, dst, size, options = self._args
                self._frame_plan = _core.Plan(src, dst, size, {**options, "threads": 1})
            return _convert_batch(job, self._frame_plan, codec, self._given)
        if out is not None:
            if isinstance(job, list) or not codec.as_is:
                raise ValueError("out: only for images of at most 4 channels of uint8, uint16, float16 or float32")
            return self._plan.run(job, out, True)
        run = lambda im, alpha: self._plan.run(im, None, alpha)  # noqa: E731
        return _arrays.run_faces(job, codec, run) if isinstance(job, list) else _arrays.run_image(job, codec, run)

    __call__ = run

    def __getstate__(self) -> Any:
        return self._args, self._given

    def __setstate__(self, state: Any) -> None:
        self._args, self._given = tuple(state[0]), state[1]
        self._plan = _core.Plan(*self._args)
        self._frame_plan = None

    def __repr__(self) -> str:
        src, dst, source_size, options = self._args
        shown = "".join(f", {k}={v!r}" for k, v in options.items() if k != "size")
        return f"Plan({src!r}, {dst!r}, source_size={source_size}, size={self.size}{shown})"


@overload
def read(path: PathLike, *, metadata: Literal[False] = ...,
         memory_limit: Union[int, str, None] = ...) -> Array: ...
@overload
def read(path: PathLike, *, metadata: Literal[True],
         memory_limit: Union[int, str, None] = ...) -> Tuple[Array, Dict[str, Any]]: ...


@_one_line_type_errors
def read(path: PathLike, *, metadata: bool = False,
         memory_limit: Union[int, str, None] = None) -> Union[Array, Tuple[Array, Dict[str, Any]]]:
    """Reads an image file (JPEG, PNG, TIFF, EXR or HDR, by its magic bytes) as an array of the
    file's sample type (other types become float32). A path with ``{face}``, ``{index}`` or
    ``{axis}`` reads six cube face files as one 6x1 cubemap in panoproj's order (``{axis}`` in its
    frame: front ``pz``, right ``px``, up ``ny``). With ``metadata=True`` returns ``(array, dict)``, the
    dict holding the file's attributes by OpenImageIO's names (EXIF, XMP, ICC profile ...)."""
    path = os.fspath(path)
    if not isinstance(path, str):
        raise TypeError(f"path: {path!r} (expected a str or os.PathLike path)")
    limit = _memory_limit(memory_limit)
    array = _core.read_faces(path, limit) if re.search(r"\{(face|index|axis)\}", path) else _core.read(path, limit)
    if metadata:
        return array, _core.read_metadata(path.replace("{face}", "front").replace("{index}", "0").replace("{axis}", "pz"))
    return array


@_takes_options("tiles")
def tiles(image: PathLike, out_dir: PathLike, *, viewer: Literal["pannellum", "marzipano"] = "pannellum",
          src: Union[str, Projection, None] = None, tile: int = 512, levels: Optional[int] = None,
          cube_size: Optional[int] = None, format: Literal["jpg", "png"] = "jpg", quality: int = 95,
          preview: Optional[int] = None, script_url: Optional[str] = None, overwrite: bool = False,
          client: Any = None, **options: Unpack[TilesOptions]) -> Dict[str, Any]:
    """Writes a multires cube tile pyramid of the panorama file ``image`` for a web viewer into the
    new folder ``out_dir`` (as ``panoproj tiles``): Pannellum's ``<level>/<face><row>_<col>`` with
    ``config.json`` and fallback faces, or Marzipano's ``tiles/<z>/<face>/<row>/<col>`` with its
    preview; ``index.html`` opens it, loading the viewer's script from ``script_url`` (default:
    the npm package on jsDelivr). Every tile is rendered from the source, antialiased at its
    level; tiles of a partial panorama without any source pixel are not written. The folder lands
    whole (replaced only with ``overwrite``).

    ``client``: a ``dask.distributed`` Client; the tiles are then rendered as tasks (bands of tile
    rows, each reading only the source region and scale it needs; the workers must see
    ``image`` and the output's parent folder at the same paths), with the same bytes as a local
    run. Returns a report: levels, tile counts, the source spec, seconds.
    """
    job = _tiles.job_of(image, out_dir, viewer=viewer, src=_spec(src), tile=tile, levels=levels,
                        cube_size=cube_size, format=format, quality=quality, preview=preview,
                        script_url=script_url, overwrite=overwrite)
    return _tiles.run(job, _core_options(options), client)


@_takes_options("views")
def views(images: Union[PathLike, Sequence[PathLike]], out_dir: PathLike, *,
          rig: Union[str, Sequence[Mapping[str, Any]]] = "cube", src: Union[str, Projection, None] = None,
          format: Literal["jpg", "png"] = "jpg", layout: Literal["flat", "folders"] = "flat", quality: int = 95,
          overwrite: bool = False, client: Any = None, **options: Unpack[ViewsOptions]) -> Dict[str, Any]:
    """Splits each panorama file of ``images`` (one path, or a sequence: one size and projection,
    each a frame) into perspective views and writes them with their cameras into the new folder
    ``out_dir`` (as ``panoproj views``): ``images/{stem}_{view}.jpg`` (or PNG; ``layout="folders"``:
    ``images/{view}/{stem}.jpg`` and ``rig_config.json`` for COLMAP's rig_configurator), for a
    partial panorama ``masks/<image's name>.png``, COLMAP's text model in ``sparse/0`` (PINHOLE
    cameras with cx = W/2 by COLMAP's pixel convention, images, one rig whose sensors are the
    views, one frame per panorama) and nerfstudio's ``transforms.json``. The world is the
    panorama's frame (x right, y down, z forward; transforms.json turns it z up).

    ``rig``: ``"cube"``, ``"ring:n=8,fov=90,pitch=0"``, a sum ``"A+B"``, ``"@rig.yaml"``, or a
    sequence of mappings with name, yaw, pitch, roll, hfov, vfov, size. ``size``: each view's
    (W, H) unless the rig gives one; default: the source's resolution.

    ``client``: a ``dask.distributed`` Client; each frame is then a task (the workers must see
    the inputs and the output's parent folder at the same paths), with the same bytes as a local
    run. Returns a report: the views (size, focal, world_from_camera), frames, source spec.
    """
    job = _views.job_of(images, out_dir, rig=rig, src=_spec(src), format=format, layout=layout, quality=quality,
                        overwrite=overwrite)
    return _views.run(job, _core_options(options), client)


@_one_line_type_errors
def write(path: PathLike, array: Array, *, overwrite: bool = False, dtype: Optional[str] = None,
          metadata: Optional[Dict[str, Any]] = None, quality: int = 95,
          subsampling: Literal["420", "422", "444"] = "420") -> None:
    """Writes an array atomically (a temporary file, then a rename): the format follows the
    extension. An existing file is replaced only with ``overwrite=True``. ``dtype`` converts the
    samples first (e.g. ``"uint8"`` for a JPEG of a float image); ``metadata`` attributes are
    written where the format has a place for them. A path with ``{face}``, ``{index}`` or
    ``{axis}`` writes a 6x1 cubemap (6N x N) as six files, all replaced or none. On any error (a full disk, no
    permission) the old file is intact and no temporary is left. JPEG: ``quality`` 1 to 100,
    ``subsampling`` of the chroma "420" (half width and height), "422" (half width) or "444"."""
    a = _arrays.as_array(array, "array")
    _core.write(os.fspath(path), a, bool(overwrite), dtype, dict(metadata or {}),
                _int("quality", quality, 1, 100, "1 to 100"), str(subsampling))


@_one_line_type_errors
def to_ray(proj: Union[str, Projection], size: SizeLike, x: Any, y: Any, *,
           convention: _coordinates.Convention = "panoproj") -> Tuple[Array, Mask]:
    """Unit rays through pixel positions (x, y) of ``proj`` at ``size`` (any shape of x, y):
    ``(rays[..., 3], ok)``; where ``ok`` is False (outside the projection) the ray is NaN.
    ``convention``: where x, y put pixel centres (panoproj: i + 0.5; opencv: i; torch: [-1, 1])."""
    convention, (w, h) = _coordinates.check(convention), _source_size(size)
    x = _coordinates.to_panoproj(convention, np.asarray(x, np.float64), w)
    y = _coordinates.to_panoproj(convention, np.asarray(y, np.float64), h)
    return _core.to_ray(str(projection(proj)), (w, h), x, y)


@_one_line_type_errors
def to_pixel(proj: Union[str, Projection], size: SizeLike, rays: Any, *,
             convention: _coordinates.Convention = "panoproj") -> Tuple[Array, Array, Mask]:
    """Pixel positions of rays (``[..., 3]``, any length but 0) in ``proj`` at ``size``:
    ``(x, y, ok)``; NaN where ``ok`` is False (the ray has no pixel). ``convention`` as in
    :func:`to_ray`."""
    convention, (w, h) = _coordinates.check(convention), _source_size(size)
    x, y, ok = _core.to_pixel(str(projection(proj)), (w, h), np.asarray(rays, np.float64))
    return _coordinates.from_panoproj(convention, x, w), _coordinates.from_panoproj(convention, y, h), ok


@_one_line_type_errors
def split_faces(image: Array, layout: Union[str, Projection] = "cubemap") -> List[Array]:
    """The six faces (front, right, back, left, up, down) of a cubemap image, as views, upright
    (a face its layout turns, ``rot=``, turned back; a padded cell whole)."""
    spec = str(projection(layout))
    face, origins = _core.face_origins(spec, (image.shape[1], image.shape[0]))
    return [np.rot90(image[y:y + face, x:x + face], k=q) for x, y, q in origins]


def simd_target() -> str:
    """The SIMD instruction set the engine dispatches to on this machine (e.g. ``AVX3``)."""
    return _core.simd_target()
