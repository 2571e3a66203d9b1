"""Type aliases of the public API (what users hand in)."""

from __future__ import annotations

import os
from typing import Any, Mapping, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

try:
    from typing import Protocol
except ImportError:  # pragma: no cover (Python 3.7)
    from typing_extensions import Protocol  # type: ignore


class SupportsDLPack(Protocol):
    def __dlpack__(self, *args: Any, **kwargs: Any) -> Any: ...


PathLike = Union[str, "os.PathLike[str]"]
SizeLike = Union[Tuple[int, int], int, str, None]  # (W, H), N for a square, "WxH" or "N"
"""(width, height) like OpenCV's dsize, or "WxH"; None: derived from the source."""
FillLike = Union[str, Sequence[float], None]
"""(r, g, b[, a]) in unit range, "R,G,B[,A]" or "#rrggbb[aa]"."""
ArrayLike = Union[npt.ArrayLike, SupportsDLPack]
"""A numpy array, or anything numpy reads as one: __array__, the buffer protocol, __dlpack__,
nested lists."""
ImageLike = Union[ArrayLike, Sequence[ArrayLike], Mapping[str, ArrayLike]]
"""An image, a batch (N, H, W, C), or a cubemap's six faces as a list or a dict."""
Array = npt.NDArray[Any]
Mask = npt.NDArray[np.bool_]
