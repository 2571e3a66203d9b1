"""panoproj: convert images between projections (pinhole, fisheye laws, calibrated lenses, dual
fisheyes, equirect, cylindrical, Panini, cube maps, world maps: ``projections()`` lists them) at
native speed, from numpy; files, videos, Hugin projects and rigs, tiles, views and COLMAP models.

Conventions (the same as the ``panoproj`` command; the documentation's Conventions page):

- Images are arrays ``HxW``, ``HxWxC`` or batches ``NxHxWxC`` of any channel count (2 or 4:
  alpha last; more than 4 in groups, no alpha): uint8, uint16, float16, float32 as they are,
  float64 through float32, any integer/bool/float with ``interp="nearest"`` exactly; anything
  numpy reads (``__dlpack__``, ``__array__``, buffers). A C-contiguous array is read in place.
- A cubemap in memory is one image in its layout (6x1 by default: front, right, back, left, up,
  down); :func:`convert` also takes six face arrays (a list, or a dict by ``F R B L U D``), and
  :func:`split_faces` gives the faces of a cubemap image as views.
- Sizes are ``(width, height)`` like OpenCV's ``dsize`` (or ``"WxH"``; ``N`` or ``"N"`` for a
  square); angles in degrees.
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

from . import _arrays, _coordinates, _core, _declared, _job, _jobs
from ._jobs import *  # noqa: F401,F403 (the jobs' functions and their options, generated)
from ._options import (_F, _core_options, _int, _memory_limit, _one_line_type_errors, _size, _takes_options,
                       _threads)
from ._declared import *  # noqa: F401,F403 (the projection classes and Literal aliases)
from ._declared import CLASSES, ConvertOptions, MapOptions, ProjectionName
from ._projection import _CLASSES, Projection, projection
from ._text import shown as _shown
from ._types import Array, FillLike, ImageLike, Mask, PathLike, SizeLike
from ._video import VideoPlan
from ._stitch import Layer, Layers, StitchPlan, stitch_layers, stitch_panorama

if TYPE_CHECKING:
    from typing import Literal

    from typing_extensions import Unpack

__version__: str = _core.__version__  # the project's version (`panoproj --version` says the same)

_CLASSES.update(CLASSES)
__all__ = [
    "Projection", "projection", "projections", "ProjectionInfo", "ParameterInfo", "convert", "build_map", "Plan",
    "VideoPlan", "stitch_layers", "stitch_panorama", "StitchPlan", "Layer", "Layers",
    "read", "write", "to_ray", "to_pixel", "split_faces", "simd_target", "ConvertOptions", "MapOptions",
    "SizeLike", "FillLike", "ImageLike", "PathLike",
]
__all__ += _declared.__all__  # the projection classes and the Literal aliases
__all__ += _jobs.__all__  # the jobs' functions and their options


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
def convert(image: Union[ImageLike, PathLike], src: Union[str, Projection, None], dst: Union[str, Projection],
            **options: Unpack[ConvertOptions]) -> Array:
    """Converts ``image`` from projection ``src`` to ``dst`` and returns the new image.

    ``image``: HxW, HxWxC, a batch NxHxWxC (frames converted in parallel on one plan, equal to
    converting each), a cubemap's six faces (a list, or a dict by ``F R B L U D``), or a GoPro
    MAX's two strips (``src="gopro-max"``: a list of stream 0:0's and 0:5's frames); numpy or
    anything numpy reads (``__array__``, ``__dlpack__``, buffers); or an image file's path, read as
    ``read`` reads it (``convert_file`` writes a file instead, keeping its metadata). The result has the input's
    dtype and channels (float64 computed in float32); pixels without a source are 0 (alpha 0).
    ``src=None`` takes a 2:1 image as a full equirect, as the command does. In Python, ``size``
    is ``(width, height)`` (or ``"WxH"``, ``N``), ``antialias`` may be a sub-pixel count ``N``, ``fill`` a
    tuple ``(r, g, b[, a])`` in unit range, and ``memory_limit`` a byte count or text such as
    ``"4G"``; a job over it raises MemoryError before any work.
    """
    if isinstance(image, (str, os.PathLike)):
        image = read(image, memory_limit=options.get("memory_limit"))
    if src is not None:
        image = _arrays.strip_pair(image, str(projection(src)))
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
    or the source taps and weights the others plan (at most 17 bytes an output pixel, 38 from a
    dual fisheye with its blend, counted against ``memory_limit``; outputs over ~30 Mpx, ~14 from
    a dual fisheye, keep nothing); later runs on images of the same dtype and channels reuse them and only gather, to
    the same bytes (uint8 bilinear: about a third of the first run's time). ``plan(image)`` or
    ``plan.run(image, out=array)`` (writes into a C-contiguous array of the output's shape and
    dtype). Takes what :func:`convert` takes
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
        given = "".join(f", {k}={v!r}" for k, v in options.items() if k != "size")
        return f"Plan({src!r}, {dst!r}, source_size={source_size}, size={self.size}{given})"


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
        raise TypeError(f"path: {_shown(path)} (expected a str or os.PathLike path)")
    limit = _memory_limit(memory_limit)
    array = _core.read_faces(path, limit) if re.search(r"\{(face|index|axis)\}", path) else _core.read(path, limit)
    if metadata:
        return array, _core.read_metadata(path.replace("{face}", "front").replace("{index}", "0").replace("{axis}", "pz"))
    return array


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
    # The write options' rows (the command's --overwrite, --quality, --subsampling), checked there.
    options = {"overwrite": bool(overwrite), "quality": _int("quality", quality, -2**63, 2**63 - 1, "1 to 100"),
               "subsampling": str(subsampling)}
    _core.write(os.fspath(path), a, options, dtype, dict(metadata or {}))


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


def __dir__() -> List[str]:
    """The API (``__all__``) and the module's own dunders, not the names it imports to work."""
    return sorted(set(__all__) | {n for n in globals() if n.startswith("__")})
