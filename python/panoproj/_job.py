"""The folder jobs' Python functions at run time (panoproj/_jobs.py, generated from the jobs' rows,
calls run): each argument checked by its row's type, or by its Python form (paths, a projection,
a rig), then the job run by the core in this process, or in parts on a Dask ``distributed``
client: the client begins the job (checks, a temporary folder beside the output), each task
renders parts into it, and the client finishes and lands the folder. The bytes equal a local
run's: each file depends only on the job's arguments."""
from __future__ import annotations

import math
import os
import time
from typing import Any, Callable, Dict, List, Mapping, Sequence, Tuple

from ._text import shown
from . import _core, _options
from ._projection import projection

# The temporary folder as the tasks carry it: (path, device, inode); each task refuses a folder
# of another identity (one swapped in meanwhile).
Staged = Tuple[str, int, int]

_ROWS = {j["name"]: {r["name"]: r for r in j["rows"]} for j in _core.jobs()}

_NUMBER_KEYS = ("yaw", "pitch", "roll", "hfov", "fov", "vfov")
_INTEGER_KEYS = ("width", "height")


def rig_text(rig: Any) -> str:
    """A rig as the core reads it: its text, or a sequence of mappings as inline YAML."""
    if isinstance(rig, str):
        return rig
    if isinstance(rig, Mapping) or not isinstance(rig, Sequence):
        raise TypeError(f"rig: {shown(rig)} (expected a str such as 'cube', or a sequence of mappings)")
    lines = []
    for i, view in enumerate(rig):
        if not isinstance(view, Mapping):
            raise TypeError(f"rig[{i}]: {shown(view)} (expected a mapping: name, yaw, pitch, roll, hfov, vfov, size)")
        items = []
        for key, value in view.items():
            where = f"rig[{i}][{shown(key)}]"
            if key == "name":
                if not isinstance(value, str):
                    raise TypeError(f"{where}: {shown(value)} (expected a str)")
                text = value
            elif key in _NUMBER_KEYS:
                if isinstance(value, bool) or not isinstance(value, (int, float)):
                    raise TypeError(f"{where}: {shown(value)} (expected a number of degrees)")
                if not math.isfinite(value):
                    raise ValueError(f"{where}: {shown(value)} (expected a finite number of degrees)")
                text = repr(float(value))
            elif key in _INTEGER_KEYS:
                if isinstance(value, bool) or not isinstance(value, int):
                    raise TypeError(f"{where}: {shown(value)} (expected an int)")
                text = str(value)
            elif key == "size":
                if (not isinstance(value, (tuple, list)) or len(value) != 2
                        or any(isinstance(v, bool) or not isinstance(v, int) for v in value)):
                    raise TypeError(f"{where}: {shown(value)} (expected (width, height) ints)")
                text = f"{value[0]}x{value[1]}"
            else:
                raise TypeError(f"rig[{i}]: unknown key {shown(key)} (expected name, yaw, pitch, roll, hfov or fov, "
                                "vfov, size, width, height)")
            if any(c in text for c in ",:{}#\n"):
                raise ValueError(f"{where}: {shown(text)} (a name of letters, digits, '_' or '-')")
            items.append(f"{key}: {text}")
        lines.append("- {" + ", ".join(items) + "}")
    if not lines:
        raise ValueError("rig: no views (expected at least one mapping)")
    return "\n".join(lines) + "\n"


def _path(name: str, v: Any) -> str:
    """A path argument as the core takes it: a str, or an os.PathLike giving one."""
    try:
        p = os.fspath(v)
    except TypeError:
        raise TypeError(f"{name}: {shown(v)} (expected a str or os.PathLike path)") from None
    if not isinstance(p, str):
        raise TypeError(f"{name}: {shown(v)} (expected a str or os.PathLike path)")
    return p


def _paths(name: str, v: Any) -> List[str]:
    if isinstance(v, (str, os.PathLike)):
        return [_path(name, v)]
    if isinstance(v, Sequence):
        return [_path(f"{name}[{i}]", p) for i, p in enumerate(v)]
    raise TypeError(f"{name}: {shown(v)} (expected a path or a sequence of paths)")


def _integer(name: str, v: Any) -> int:
    if isinstance(v, bool) or not isinstance(v, int):
        raise TypeError(f"{name}: {shown(v)} (expected an int)")
    if not -(1 << 62) < v < (1 << 62):
        raise ValueError(f"{name}: {v} is out of range")
    return v


def _text(name: str, v: Any) -> str:
    if not isinstance(v, str):
        raise TypeError(f"{name}: {shown(v)} (expected a str)")
    return v


def _time(name: str, v: Any) -> str:
    """A time or rate: a number (seconds, frames a second) or the command's text of one."""
    if isinstance(v, bool) or not isinstance(v, (int, float, str)):
        raise TypeError(f"{name}: {shown(v)} (expected a number or a str such as '1:30')")
    if isinstance(v, str):
        return v
    if not math.isfinite(v):
        raise ValueError(f"{name}: {shown(v)} (expected a finite number)")
    return repr(float(v))


# Rows with Python forms of their own: a projection (or its spec), a rig as mappings, times.
_BY_NAME: Dict[str, Callable[[str, Any], Any]] = {
    "src": lambda name, v: str(projection(v)),
    "dst": lambda name, v: str(projection(v)),
    "rig": lambda name, v: rig_text(v),
    "start": _time,
    "duration": _time,
    "fps": _time,
}
_BY_TYPE: Dict[str, Callable[[str, Any], Any]] = {
    "path": _path, "paths": _paths, "integer": _integer, "text": _text, "flag": lambda name, v: bool(v),
    "angle": _options._angle,
}


def arguments(job: str, given: Dict[str, Any], options: Dict[str, Any]) -> Dict[str, Any]:
    """The job's arguments as the core takes them: those given (None: the row's default), then the
    conversion options."""
    rows, out = _ROWS[job], {}
    for name, v in given.items():
        if v is not None:
            row = rows[name]
            out[name] = (_BY_NAME.get(name) or _BY_TYPE[row["type"]])(name, v)
    out.update(_options._core_options(options))
    return out


def _render(job: str, args: Dict[str, Any], folder: Staged, part: int) -> Tuple[int, int]:
    """One task: part ``part`` written into ``folder``; returns (written, empty)."""
    written, empty = _core.job_render(job, args, folder, [part])
    return int(written), int(empty)


def _on_client(client: Any, job: str, args: Dict[str, Any]) -> Dict[str, Any]:
    """Begins the job, a task per part on the client, then finishes it with the counts' sums;
    any failure abandons it (the folder removed)."""
    t0 = time.perf_counter()
    folder, parts = _core.job_begin(job, args)
    try:
        futures = [client.submit(_render, job, args, folder, part, pure=False) for part in range(parts)]
        counts: List[Tuple[int, int]] = client.gather(futures)
        report = dict(_core.job_finish(job, args, folder, [sum(c[0] for c in counts), sum(c[1] for c in counts)]))
    except BaseException:
        _core.job_abandon(folder)
        raise
    report["seconds"] = time.perf_counter() - t0
    report["tasks"] = len(futures)
    return report


def run(job: str, given: Dict[str, Any], options: Dict[str, Any], client: Any = None) -> Dict[str, Any]:
    """The job: in this process, or as one task a part on ``client`` (a dask.distributed Client)."""
    args = arguments(job, given, options)
    return dict(_core.job_run(job, args)) if client is None else _on_client(client, job, args)
