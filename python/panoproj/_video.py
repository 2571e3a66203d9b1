"""VideoPlan: a Plan over a video's frames as PyAV decodes them, in their own pixel format."""
from __future__ import annotations

import warnings
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from ._text import shown
from . import _core, _pyav
from ._options import _core_options, _one_line_type_errors, _takes_options
from ._projection import Projection, projection
from ._types import Array

if TYPE_CHECKING:
    from typing_extensions import Unpack

    from ._declared import ConvertOptions

_SITINGS = {"left": 1, "center": 2, "topleft": 3, "top": 4, "bottomleft": 5, "bottom": 6}


def _described(like: Any) -> Tuple[str, Tuple[int, int], Any, str]:
    """The pixel format, size, colour source and codec of a PyAV frame or video stream."""
    if hasattr(like, "planes") and hasattr(like, "format"):  # av.VideoFrame
        return like.format.name, (like.width, like.height), like, ""
    cc = getattr(like, "codec_context", None)
    if cc is not None and getattr(cc, "format", None) is not None:  # a video stream
        return cc.format.name, (cc.width, cc.height), cc, cc.name
    raise TypeError(f"like: {type(like).__name__} (expected an av.VideoFrame or a video stream of PyAV)")


class VideoPlan:
    """One conversion geometry for a video's frames (PyAV's ``av.VideoFrame``), each converted
    plane by plane in its own pixel format as ``panoproj convert`` converts a video: Y, Cb, Cr (or
    G, B, R) and alpha of 8 to 16 bits, each chroma plane on its own map at its resolution and at
    the sited position of its samples; outside the source's field video black.

    ``like``: a frame (or a PyAV video stream) of the video: its pixel format, size and colour
    (formats that are not planar, e.g. NV12 or P010, are converted to their planar form with the
    same samples first: a copy). ``chroma_siting``: where the chroma samples sit ("left",
    "center", "topleft", ...); default: the codec's usual, as PyAV does not give a stream's. Takes
    convert's options; an output size that does not hold whole chroma samples is made the next
    that does (a warning), or refused where ``size`` is given.

    ``plan(frame)`` returns a new ``av.VideoFrame`` of that format with the frame's time and
    colour; ``plan.run(frame, out=frame2)`` writes into ``frame2`` (of the output's size and
    format). A plane whose rows are back to back (PyAV pads rows to 32 or 64 bytes: widths that
    are multiples of that) is read and written in place, others are copied once.
    :meth:`run_planes` takes and gives the planes as numpy arrays. Safe to call from several
    threads at once; pickles as its parameters.
    """

    __slots__ = ("_state", "_plan", "_format")

    @_one_line_type_errors
    @_takes_options("convert")
    def __init__(self, src: Any, dst: Any, like: Any, *, chroma_siting: Optional[str] = None,
                 **options: Unpack[ConvertOptions]) -> None:
        name, size, colour, codec = _described(like)
        planar = _pyav.planar(name)
        if planar is None:
            raise ValueError(f"like: pixel format {name} has no planar form of 8 to 16 bits a sample")
        px = _pyav.pixels(planar, colour.color_range, colour.colorspace, colour.color_primaries, colour.color_trc,
                          codec)
        if chroma_siting is not None:
            if chroma_siting not in _SITINGS:
                raise ValueError(f"chroma_siting: {shown(chroma_siting)} (expected one of {', '.join(_SITINGS)})")
            px["siting"], px["siting_said"] = _SITINGS[chroma_siting], True
        self._build((str(projection(src)), str(projection(dst)), px, size, _core_options(options)), name)
        for line in self._plan.warnings:
            warnings.warn(line, UserWarning, stacklevel=3)

    def _build(self, state: Tuple[str, str, Dict[str, Any], Tuple[int, int], Dict[str, Any]], name: str) -> None:
        self._state, self._format = state, name
        src, dst, px, size, options = state
        self._plan = _core.VideoPlan(px, size, src, dst, options)

    @property
    def src(self) -> Projection:
        return projection(self._state[0])

    @property
    def dst(self) -> Projection:
        return projection(self._state[1])

    @property
    def pixel_format(self) -> str:
        """The planes' format (the frames' own, or its planar form)."""
        return str(self._state[2]["pixel_format"])

    @property
    def source_size(self) -> Tuple[int, int]:
        return self._state[3]

    @property
    def size(self) -> Tuple[int, int]:
        """The output's (width, height)."""
        return self._plan.plane_size(0, True)

    def plane_sizes(self, output: bool = True) -> List[Tuple[int, int]]:
        """Each plane's (width, height) in the output (or the source)."""
        return [self._plan.plane_size(p, output) for p in range(int(self._state[2]["planes"]))]

    def _dtype(self) -> Any:
        return np.dtype("<u2") if self._state[2]["bits"] > 8 else np.dtype(np.uint8)

    @_one_line_type_errors
    def run_planes(self, planes: Sequence[Array], out: Optional[Sequence[Array]] = None) -> List[Array]:
        """Converts one frame's planes (2-D arrays of the source's plane sizes, uint8, or uint16
        for 9 to 16 bits); with ``out``, into those arrays (C-contiguous, writable)."""
        dtype = self._dtype()
        ins = [np.ascontiguousarray(p) for p in planes]
        for i, p in enumerate(ins):
            if p.dtype != dtype:
                raise TypeError(f"planes[{i}]: {p.dtype} (expected {dtype} for {self.pixel_format})")
        outs = list(out) if out is not None else [np.empty(s[::-1], dtype) for s in self.plane_sizes()]
        self._plan.run(ins, outs)
        return outs

    @_one_line_type_errors
    def run(self, frame: Any, out: Any = None) -> Any:
        """Converts ``frame`` (an ``av.VideoFrame`` of the plan's size and format) into a new
        frame, or into ``out``; returns it with the frame's time and colour."""
        av = _pyav.require()
        if not isinstance(frame, av.VideoFrame):
            raise TypeError(f"frame: {type(frame).__name__} (expected an av.VideoFrame)")
        if (frame.width, frame.height) != self.source_size or frame.format.name != self._format:
            raise ValueError(f"frame: {frame.width}x{frame.height} {frame.format.name} (the plan is for "
                             f"{self.source_size[0]}x{self.source_size[1]} {self._format})")
        if frame.format.name != self.pixel_format:
            frame = frame.reformat(format=self.pixel_format, interpolation="POINT")
        w, h = self.size
        if out is None:
            out = av.VideoFrame(w, h, self.pixel_format)
        elif (not isinstance(out, av.VideoFrame) or (out.width, out.height) != (w, h)
              or out.format.name != self.pixel_format):
            raise ValueError(f"out: expected an av.VideoFrame of {w}x{h} {self.pixel_format}")
        dtype = self._dtype()
        views = _pyav.plane_views(out, dtype)
        targets = [v if v.flags.c_contiguous else np.empty(v.shape, dtype) for v in views]
        self.run_planes(_pyav.plane_views(frame, dtype), targets)
        for v, t in zip(views, targets):
            if v is not t:
                v[...] = t
        out.pts, out.time_base = frame.pts, frame.time_base
        out.color_range, out.colorspace = frame.color_range, frame.colorspace
        out.color_primaries, out.color_trc = frame.color_primaries, frame.color_trc
        return out

    __call__ = run

    def __getstate__(self) -> Any:
        return self._state, self._format

    def __setstate__(self, state: Any) -> None:
        self._build(tuple(state[0]), state[1])  # type: ignore[arg-type]

    def __repr__(self) -> str:
        src, dst, px, size, options = self._state
        given = "".join(f", {k}={v!r}" for k, v in options.items() if k != "size")
        return (f"VideoPlan({src!r}, {dst!r}, {size[0]}x{size[1]} {px['pixel_format']}, size={self.size}{given})")
