"""Pixel coordinate conventions, all of one axis of ``size`` pixels:

- ``"panoproj"``: pixel i covers [i, i + 1), its centre at i + 0.5;
- ``"opencv"``: centres at integers (``cv2.remap``, camera matrices' cx, cy);
- ``"torch"``: normalized to [-1, 1] across the frame's edges, as ``torch.nn.functional.grid_sample``
  reads its grid with ``align_corners=False``: x_t = 2 x / size - 1 for panoproj's x.
"""

from __future__ import annotations

from typing import Literal, Tuple

import numpy as np

from ._text import shown

Convention = Literal["panoproj", "opencv", "torch"]
_NAMES = ("panoproj", "opencv", "torch")


def check(convention: object) -> str:
    if convention not in _NAMES:
        raise ValueError(f"convention: {shown(convention)} (expected 'panoproj', 'opencv' or 'torch')")
    return str(convention)


def to_panoproj(convention: str, v: np.ndarray, size: int) -> np.ndarray:
    if convention == "opencv":
        return v + 0.5
    if convention == "torch":
        return (v + 1.0) * (size / 2.0)
    return v


def from_panoproj(convention: str, v: np.ndarray, size: int) -> np.ndarray:
    if convention == "opencv":
        return v - 0.5
    if convention == "torch":
        return v * (2.0 / size) - 1.0
    return v


def torch_grid(map_x: np.ndarray, map_y: np.ndarray, source_size: Tuple[int, int]) -> np.ndarray:
    """(H, W, 2) float32 of panoproj-convention maps; -2 (outside [-1, 1]: grid_sample's padding)
    where there is no source."""
    w, h = source_size
    grid = np.empty(map_x.shape + (2,), np.float32)
    grid[..., 0] = from_panoproj("torch", map_x, w)
    grid[..., 1] = from_panoproj("torch", map_y, h)
    grid[np.isnan(grid)] = -2.0
    return grid
