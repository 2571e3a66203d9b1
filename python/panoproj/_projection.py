"""The base of the projection classes (generated in _declared.py, one per catalogue name) and
spec text <-> instances."""

from __future__ import annotations

import numbers
from typing import Any, Dict, Tuple, Union

import numpy as np

from ._text import shown
from . import _core


class Projection:
    """A projection spec: a name and parameters, as in ``"fisheye:fov=180,model=equisolid"``.

    Build one from keywords with the subclass (``Fisheye(fov=180, model="equisolid")``) or from
    spec text with :func:`projection`. Parameters not given take their defaults, some derived
    from the image size when the projection is used (``panoproj info`` lists them all).
    """

    name: str = ""
    summary: str = ""

    def _set(self, **params: Any) -> None:
        parts = [f"{k}={_text(k, v)}" for k, v in params.items() if v is not None]
        self._text = _core.canonical(self.name + (":" + ",".join(parts) if parts else ""))

    @property
    def params(self) -> Dict[str, Union[float, int, str]]:
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

    def __reduce__(self) -> Tuple[Any, Tuple[str]]:
        return (projection, (self._text,))


def _text(key: str, v: Any) -> str:
    """A key's value as spec text: names as they are, integers (numpy's too) exactly, floats by
    their shortest text that reads back to the same double."""
    if isinstance(v, str):
        return v
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, (numbers.Integral, numbers.Real)):
        raise TypeError(f"{key}: {shown(v)} (expected a number or a name)")
    return str(int(v)) if isinstance(v, numbers.Integral) else repr(float(v))


def _value(text: str) -> Union[float, int, str]:
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


_CLASSES: Dict[str, type] = {}


def projection(spec: Union[str, Projection]) -> Projection:
    """The projection of spec text (``"pinhole:hfov=90"``), as an instance of its class."""
    if isinstance(spec, Projection):
        return spec
    if not isinstance(spec, str):
        raise TypeError(f"projection: {shown(spec)} (expected spec text such as 'pinhole:hfov=90', or a Projection)")
    text = _core.canonical(spec)
    cls = _CLASSES[text.partition(":")[0]]
    p = cls.__new__(cls)
    p._text = text
    return p
