"""A value as messages show it: its repr, an array by its shape and dtype, cut at 80 characters
(a message is one line)."""
from __future__ import annotations

from typing import Any

import numpy as np


def shown(v: Any) -> str:
    if isinstance(v, np.ndarray):
        return f"an array of shape {v.shape} and dtype {v.dtype}"
    r = repr(v)
    return r if len(r) <= 80 else r[:77] + "..."
