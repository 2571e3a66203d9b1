"""The keyword options, declared once in C++ (lib/src/engine/options.cpp and each job's rows): each
value checked here by its row's type (a few by name, for their Python forms) and handed to the
core, and the decorators that give the public functions their options' keywords."""
from __future__ import annotations

import ast
import difflib
import functools
import inspect
import re
from typing import TYPE_CHECKING, Any, Callable, Dict, Optional, Tuple, TypeVar, Union, cast

import numpy as np

from ._text import shown
from . import _core
from ._types import FillLike, SizeLike

_MAX_SIDE = 2**31 - 1


def _size(size: SizeLike) -> Optional[Tuple[int, int]]:
    if size is None:
        return None
    if isinstance(size, str):
        # "WxH" (either x) or "N" for a square, as the command takes them.
        m = re.fullmatch(r"\s*(\d+)\s*(?:[xX]\s*(\d+)\s*)?", size)
        if not m:
            raise ValueError(f"size: {shown(size)} (expected WxH, e.g. 4096x2048, or N for a square)")
        w = int(m.group(1))
        h = int(m.group(2)) if m.group(2) is not None else w
    elif isinstance(size, (int, np.integer)) and not isinstance(size, bool):
        w = h = int(size)
    else:
        try:
            w, h = size
        except (TypeError, ValueError):
            raise TypeError(f"size: {shown(size)} (expected (width, height))") from None
        if not all(isinstance(v, (int, np.integer)) and not isinstance(v, bool) for v in (w, h)):
            raise TypeError(f"size: {shown(size)} (expected two integers, (width, height))")
        w, h = int(w), int(h)
    if not (1 <= w <= _MAX_SIDE and 1 <= h <= _MAX_SIDE):
        raise ValueError(f"size: {w}x{h} (expected 1 to {_MAX_SIDE} pixels a side)")
    return w, h


def _int(name: str, v: Any, lo: int, hi: int, expected: str) -> int:
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
        raise TypeError(f"{name}: {shown(v)} (expected an integer, {expected})")
    if not lo <= int(v) <= hi:
        raise ValueError(f"{name}: {int(v)} (expected {expected})")
    return int(v)


def _threads(threads: Any) -> int:
    return _int("threads", threads, 0, 1024, "0 for all cores, or 1 to 1024")


def _angle(name: str, v: Any) -> float:
    try:
        return float(v)
    except OverflowError:
        raise ValueError(f"{name}: {shown(v)} (expected a finite angle in degrees)") from None
    except (TypeError, ValueError):
        raise TypeError(f"{name}: {shown(v)} (expected a number of degrees)") from None


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
    raise TypeError(f"antialias: {shown(antialias)} (expected 'auto', 'off', 'mip', a sub-pixel count or None)")




def _fill(fill: FillLike) -> Optional[str]:
    if fill is None or isinstance(fill, str):
        return fill
    try:
        values = [float(v) for v in fill]
    except (TypeError, ValueError):
        raise TypeError(f"fill: {shown(fill)} (expected 'R,G,B[,A]', '#rrggbb[aa]' or a sequence of 3 or 4 numbers)") from None
    return ",".join(repr(v) for v in values)


# The conversion options, declared once in C++ (lib/src/engine/options.cpp): each is a keyword of
# convert / build_map / Plan where the table says so, its value checked here by its type (a few
# by name, for their Python forms) and handed to the row's setter.
_OPTIONS = _core.options()
_CHOICES = {o["name"]: o["choices"].split("|") for o in _OPTIONS if o["choices"]}


def _option_text(name: str, v: Any) -> str:
    if not isinstance(v, str):
        raise TypeError(f"{name}: {shown(v)} (expected text)")
    choices = _CHOICES.get(name)
    if choices and v not in choices:
        near = difflib.get_close_matches(v, choices, 1)
        raise ValueError(f"{name}: {shown(v)} (expected one of {', '.join(choices)}"
                         + (f"; did you mean {shown(near[0])}?)" if near else ")"))
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


_JOB_OPTIONS = {j["name"]: [r for r in j["rows"] if r["conversion"]] for j in _core.jobs()}


def _takes_options(use: str, job: bool = False) -> Callable[[_F], _F]:
    """Gives fn (declared with ``**options``) the table's options for ``use`` (a job's name with
    ``job``: that job's conversion rows) as keyword-only arguments, with their defaults, in its
    runtime signature and docstring; unknown keywords raise TypeError naming the ones it takes."""
    rows = _JOB_OPTIONS[use] if job else [o for o in _OPTIONS if use in o["use"]]
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
                raise TypeError(f"{fn.__qualname__}: unknown option {shown(bad[0])} ("
                                + (f"did you mean {shown(near[0])}? " if near else "") + f"expected one of: {expected})")
            return fn(*args, **kwargs)

        keywords = [inspect.Parameter(o["name"], inspect.Parameter.KEYWORD_ONLY, default=ast.literal_eval(o["default"]))
                    for o in rows]
        call.__signature__ = sig.replace(parameters=fixed + keywords)  # type: ignore[attr-defined]
        call.__doc__ = (fn.__doc__ or "") + "\n    Options (the command's flags of the same names):\n" + "\n".join(
            f"      {o['name']} = {o['default']}: {o['help']}" for o in rows) + "\n"
        return cast(_F, call)
    return wrap
