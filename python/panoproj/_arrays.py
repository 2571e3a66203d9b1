"""Arrays as users hold them, turned into what the core takes (HxW or HxWxC, C <= 4, uint8,
uint16, float16 or float32, six faces as a list) and back:

- float64 goes through float32 and comes back as float64 (float32's ~7 digits);
- with ``interp="nearest"`` every dtype goes through as its bytes (uint8 or uint16 lanes), so
  labels, ids and masks of any integer, bool or float type come back exactly;
- more than 4 channels go through in groups of 4, none of them alpha;
- objects with ``__dlpack__`` (torch, JAX, CuPy on the CPU), ``__array__``, the buffer protocol
  (memoryview, PIL images) or nested lists are read by numpy;
- a list or tuple of six image arrays, or a dict by face (``F R B L U D`` or ``front right back
  left up down``), is a cubemap's faces.
"""

from __future__ import annotations

from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np

from . import _core

_NATIVE = (np.uint8, np.uint16, np.float16, np.float32)
_FACE_KEYS = (("F", "R", "B", "L", "U", "D"), ("front", "right", "back", "left", "up", "down"))
_GROUP = 4  # the core's channels per image

CoreInput = Union[np.ndarray, List[np.ndarray]]


def as_array(obj: Any, what: str = "image") -> np.ndarray:
    """numpy's view of an array-like (no copy where numpy can view it)."""
    if isinstance(obj, np.ndarray):
        return obj
    if isinstance(obj, (str, bytes)) or obj is None:
        raise TypeError(f"{what}: {type(obj).__name__} (expected an array: numpy, or anything with "
                        "__array__ or __dlpack__; read files with panoproj.read)")
    try:
        if hasattr(obj, "__dlpack__") and not hasattr(obj, "__array__"):
            return np.from_dlpack(obj)
        return np.asarray(obj)
    except (TypeError, ValueError, RuntimeError, BufferError) as e:
        raise TypeError(f"{what}: a {type(obj).__name__} numpy cannot read ({str(e).splitlines()[0]}; move it to the "
                        "CPU or pass a numpy array)") from None


def _looks_like_image(obj: Any) -> bool:
    return isinstance(obj, np.ndarray) and obj.ndim >= 2 or (
        not isinstance(obj, (list, tuple, str, bytes)) and any(
            hasattr(obj, a) for a in ("__array__", "__dlpack__", "__array_interface__")))


def faces_of(image: Any) -> Optional[List[np.ndarray]]:
    """The six faces when ``image`` is a cubemap's faces (a dict, or a list/tuple of six images); else None."""
    if isinstance(image, Mapping):
        for keys in _FACE_KEYS:
            if set(image) == set(keys):
                return [as_array(image[k], f"face {k}") for k in keys]
        raise ValueError(f"cube faces: keys {sorted(map(str, image))} (expected F R B L U D, or front right back "
                         "left up down)")
    if isinstance(image, (list, tuple)) and image and all(_looks_like_image(f) for f in image):
        if len(image) != 6:
            raise ValueError(f"cube faces: {len(image)} arrays (expected 6: front right back left up down)")
        return [as_array(f, "face") for f in image]
    return None


def strip_pair(image: Any, src: str) -> Any:
    """A GoPro MAX source given as its two strips (a list or tuple: stream 0:0's frame, then 0:5's;
    frames or batches) as the one frame the form holds, the first above the second; else image."""
    if not (src.split(":")[0] == "gopro-max" and isinstance(image, (list, tuple))):
        return image
    if len(image) != 2:
        raise ValueError(f"gopro-max: {len(image)} arrays (expected the two strips of one frame, stream 0:0's first, "
                         "or one array of both stacked)")
    a, b = as_array(image[0], "strip 0"), as_array(image[1], "strip 1")
    if a.shape != b.shape or a.dtype != b.dtype:
        raise ValueError(f"gopro-max: strips of shapes {a.shape} {a.dtype} and {b.shape} {b.dtype} (expected one frame of "
                         "each stream: equal shapes and dtypes)")
    return np.concatenate([a, b], axis=-3 if a.ndim >= 3 else 0)


def check_layout(a: np.ndarray, what: str = "array") -> None:
    """HxW, HxWxC or NxHxWxC; a channels-first array gets the transpose it needs."""
    if a.ndim not in (2, 3, 4):
        raise ValueError(f"{what} shape {a.shape}: {a.ndim} dimensions (expected HxW, HxWxC, or NxHxWxC for a batch)")
    if a.ndim >= 3 and 1 <= a.shape[-3] <= 4 and a.shape[-1] > 4:
        raise ValueError(f"{what} shape {a.shape}: channels first (CHW) (expected channels last: "
                         "np.moveaxis(a, -3, -1))")
    if a.ndim >= 3 and a.shape[-1] < 1 or a.shape[0] < 1 or a.shape[1] < 1:
        raise ValueError(f"{what} shape {a.shape}: empty (expected at least 1x1 pixels and 1 channel)")


class Codec:
    """How one dtype and channel count go through the core, and come back."""

    def __init__(self, dtype: np.dtype, channels: int, nearest: bool) -> None:
        self.dtype = dtype
        self.lanes: Optional[type] = None  # the uint type samples travel as, bit for bit
        self.through: Optional[type] = None  # float32 for float64
        if dtype.type in _NATIVE:
            pass
        elif nearest and dtype.kind in "biuf" and dtype.itemsize in (1, 2, 4, 8):
            self.lanes = np.uint8 if dtype.itemsize == 1 else np.uint16
        elif dtype == np.float64:
            self.through = np.float32
        elif dtype.kind in "biu":
            raise TypeError(f"array dtype {dtype}: integers other than uint8/uint16 and bool are labels, copied "
                            "exactly by interp='nearest' (or pass a.astype(np.float32) to interpolate)")
        else:
            raise TypeError(f"array dtype {dtype} (expected uint8, uint16, float16, float32 or float64; any integer "
                            "or bool with interp='nearest')")
        per = dtype.itemsize // 2 if self.lanes is np.uint16 else 1
        self.channels = channels * per  # channels as the core sees them
        self.groups = -(-self.channels // _GROUP)
        # Channels 2 and 4 are alpha only for images the core sees whole, as they are.
        self.alpha = self.groups == 1 and self.lanes is None
        self.as_is = self.alpha and self.through is None  # the core takes and gives the user's arrays

    def encode(self, a: np.ndarray) -> List[np.ndarray]:
        if self.lanes is not None:
            b = np.ascontiguousarray(a if a.ndim == 3 else a[..., None])
            a = b.view(self.lanes)
        elif self.through is not None:
            a = a.astype(self.through)
        if self.groups == 1:
            return [a]
        return [a[..., g:g + _GROUP] for g in range(0, self.channels, _GROUP)]

    def decode(self, outs: List[np.ndarray], flat: bool) -> np.ndarray:
        if len(outs) == 1 and self.lanes is None:
            out = outs[0]
        else:
            out = np.concatenate([o if o.ndim == 3 else o[..., None] for o in outs], axis=-1)
        if self.lanes is not None:
            out = out.view(self.dtype)
        elif self.through is not None:
            out = out.astype(self.dtype)
        if flat and out.ndim == 3 and out.shape[-1] == 1:
            out = out[..., 0]
        return out


def refuse_alpha(codec: Codec, options: Dict[str, Any]) -> None:
    for key in ("alpha", "fill"):
        if options.get(key) and not codec.alpha:
            kind = "its samples as bytes (interp='nearest')" if codec.lanes else f"{codec.channels} channels in groups"
            raise ValueError(f"{key}: this {codec.dtype} image goes through as {kind}, with no alpha channel to add "
                             "or fill (convert without it, or pass at most 4 channels of uint8, uint16, float16 or "
                             "float32)")


Run = Callable[[CoreInput, bool], np.ndarray]


def run_image(image: np.ndarray, codec: Codec, run: Run) -> np.ndarray:
    return codec.decode([run(g, codec.alpha) for g in codec.encode(image)], image.ndim == 2)


def run_faces(faces: Sequence[np.ndarray], codec: Codec, run: Run) -> np.ndarray:
    encoded = [codec.encode(f) for f in faces]
    return codec.decode([run([e[g] for e in encoded], codec.alpha) for g in range(codec.groups)], faces[0].ndim == 2)


def codec_for(a: np.ndarray, interp: Any) -> Codec:
    return Codec(a.dtype, a.shape[-1] if a.ndim in (3, 4) else 1, interp == "nearest")
