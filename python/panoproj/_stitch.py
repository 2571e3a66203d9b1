"""A Hugin project's layers, or its blended panorama, as arrays: the stitch job's rendering (the
same pixels as its files), without files."""
from __future__ import annotations

import sys
from typing import TYPE_CHECKING, List, NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np

from . import _core, _job
from ._declared import StitchOptions
from ._types import PathLike

if sys.version_info >= (3, 8):
    from typing import Literal
if TYPE_CHECKING:
    from typing_extensions import Unpack


class Layer(NamedTuple):
    """One image's layer: its index in the project, its pixels (H x W x 4, or x 2 for a gray image;
    alpha last, 0 or full), the canvas position of its top-left pixel and, for HDR layers, nona's
    weights (H x W uint8: each kept pixel's largest code value, the ``_gray.pgm`` file's)."""

    image: int
    pixels: np.ndarray
    offset: Tuple[int, int]
    weights: Optional[np.ndarray] = None


class Layers(NamedTuple):
    """The layers in the project's order (images without a pixel on the canvas left out) and the
    canvas's (width, height)."""

    layers: List[Layer]
    canvas: Tuple[int, int]


def stitch_layers(
    project: PathLike,
    *,
    images: Union[PathLike, Sequence[PathLike], None] = None,
    to: Optional[str] = None,
    image: Optional[int] = None,
    extent: Optional[Literal["crop", "canvas"]] = None,
    depth: Optional[Literal["uint8", "uint16", "float"]] = None,
    exposure: Optional[float] = None,
    ignore_exposure: bool = False,
    output_mode: Optional[Literal["ldr", "hdr"]] = None,
    **options: Unpack[StitchOptions],
) -> Layers:
    """Remaps a Hugin project's (.pto) images, or a rig's lenses (.yaml, .yml, .json; its panorama
    ``to`` at ``size``), onto its panorama as ``stitch`` does, returning the layers as arrays with
    their offsets instead of writing them."""
    given = {"project": project, "output": "", "images": images, "to": to, "image": image, "extent": extent,
             "depth": depth,
             "exposure": exposure, "ignore_exposure": ignore_exposure, "output_mode": output_mode}
    args = _job.arguments("stitch", given, dict(options))
    layers, canvas = _core.stitch_layers(args)
    return Layers([Layer(i, a, (int(x), int(y)), w) for i, a, (x, y), w in layers],
                  (int(canvas[0]), int(canvas[1])))


def stitch_panorama(
    project: PathLike,
    *,
    images: Union[PathLike, Sequence[PathLike], None] = None,
    to: Optional[str] = None,
    image: Optional[int] = None,
    depth: Optional[Literal["uint8", "uint16", "float"]] = None,
    exposure: Optional[float] = None,
    ignore_exposure: bool = False,
    output_mode: Optional[Literal["ldr", "hdr"]] = None,
    blend: Optional[Literal["feather", "multiband"]] = None,
    feather: Optional[float] = None,
    levels: Optional[int] = None,
    **options: Unpack[StitchOptions],
) -> np.ndarray:
    """Blends a Hugin project's (.pto) images, or a rig's lenses (.yaml, .yml, .json; its panorama
    ``to`` at ``size``), into its panorama as ``stitch project.pto pano.jpg`` does, returning the
    canvas (H x W x 4, or x 2 where every image is gray; alpha last: full where an image covers)
    instead of writing it."""
    given = {"project": project, "output": "", "images": images, "to": to, "image": image, "depth": depth,
             "exposure": exposure, "ignore_exposure": ignore_exposure, "output_mode": output_mode,
             "blend": blend, "feather": feather, "levels": levels}
    args = _job.arguments("stitch", given, dict(options))
    pixels, _levels = _core.stitch_panorama(args)
    return pixels


class StitchPlan:
    """A rig's (or a template project's) panorama over frames in memory, for video loops: the
    plan (each lens's geometry, margins and seams: content-free) is made once, at the first call,
    from its frames' shapes; each call blends one set of frames (one array per input: a rig's in
    the order it first names them, a project's per image) into the panorama (H x W x 4, alpha
    last), as :func:`stitch_panorama` would from files holding them. Later frames keep the first
    ones' shapes. Options as :func:`stitch_panorama`'s."""

    def __init__(
        self,
        project: PathLike,
        *,
        to: Optional[str] = None,
        depth: Optional[Literal["uint8", "uint16", "float"]] = None,
        blend: Optional[Literal["feather", "multiband"]] = None,
        feather: Optional[float] = None,
        levels: Optional[int] = None,
        **options: Unpack[StitchOptions],
    ) -> None:
        given = {"project": project, "output": "", "to": to, "depth": depth, "blend": blend,
                 "feather": feather, "levels": levels}
        self._args = _job.arguments("stitch", given, dict(options))
        self._core: Optional[_core.ArrayStitch] = None

    def __call__(self, frames: Sequence[np.ndarray]) -> np.ndarray:
        frames = [np.asarray(f) for f in frames]
        if self._core is None:
            self._core = _core.ArrayStitch(self._args, frames)
        return self._core(frames)

    @property
    def canvas(self) -> Tuple[int, int]:
        """The panorama's (width, height), once planned (after the first call)."""
        if self._core is None:
            raise RuntimeError("StitchPlan: planned at its first call (give it frames first)")
        return self._core.canvas


__all__ = ["stitch_layers", "stitch_panorama", "StitchPlan", "Layer", "Layers"]
