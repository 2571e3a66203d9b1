"""Panoramas split into perspective views with COLMAP and nerfstudio cameras (the command's
``panoproj views``), locally or on a Dask ``distributed`` client: the client begins the job
(every input checked, a temporary folder beside the output), each task renders one frame's
views into it, and the client finishes (camera files) and lands the folder. The bytes equal a
local run's: each view depends only on the job."""
from __future__ import annotations

import math
import os
import time
from typing import Any, Dict, Mapping, Optional, Sequence, Tuple, Union

from . import _core, _staged
from ._staged import Staged

RigLike = Union[str, Sequence[Mapping[str, Any]]]

_NUMBER_KEYS = ("yaw", "pitch", "roll", "hfov", "fov", "vfov")
_INTEGER_KEYS = ("width", "height")


def render_frame(job: Dict[str, Any], options: Dict[str, Any], folder: Staged, frame: int) -> Tuple[int, int]:
    """One task: frame ``frame``'s views written into ``folder``; returns (written, empty)."""
    written, empty = _core.views_render(job, options, folder, [frame])
    return int(written), int(empty)


def run(job: Dict[str, Any], options: Dict[str, Any], client: Any = None) -> Dict[str, Any]:
    """Every frame: in this process, or one task a frame on ``client`` (a dask.distributed Client)."""
    if client is None:
        return dict(_core.views(job, options))
    t0 = time.perf_counter()
    folder = _core.views_begin(job, options)
    return _staged.run_on_client(client, render_frame, job, options, folder, range(len(job["inputs"])),
                                 _core.views_finish, _core.views_abandon, t0)


def rig_text(rig: Any) -> str:
    """A rig as the core reads it: its text, or a sequence of mappings as inline YAML."""
    if isinstance(rig, str):
        return rig
    if isinstance(rig, Mapping) or not isinstance(rig, Sequence):
        raise TypeError(f"rig: {rig!r} (expected a str such as 'cube', or a sequence of mappings)")
    lines = []
    for i, view in enumerate(rig):
        if not isinstance(view, Mapping):
            raise TypeError(f"rig[{i}]: {view!r} (expected a mapping: name, yaw, pitch, roll, hfov, vfov, size)")
        items = []
        for key, value in view.items():
            where = f"rig[{i}][{key!r}]"
            if key == "name":
                if not isinstance(value, str):
                    raise TypeError(f"{where}: {value!r} (expected a str)")
                text = value
            elif key in _NUMBER_KEYS:
                if isinstance(value, bool) or not isinstance(value, (int, float)):
                    raise TypeError(f"{where}: {value!r} (expected a number of degrees)")
                if not math.isfinite(value):
                    raise ValueError(f"{where}: {value!r} (expected a finite number of degrees)")
                text = repr(float(value))
            elif key in _INTEGER_KEYS:
                if isinstance(value, bool) or not isinstance(value, int):
                    raise TypeError(f"{where}: {value!r} (expected an int)")
                text = str(value)
            elif key == "size":
                if (not isinstance(value, (tuple, list)) or len(value) != 2
                        or any(isinstance(v, bool) or not isinstance(v, int) for v in value)):
                    raise TypeError(f"{where}: {value!r} (expected (width, height) ints)")
                text = f"{value[0]}x{value[1]}"
            else:
                raise TypeError(f"rig[{i}]: unknown key {key!r} (expected name, yaw, pitch, roll, hfov or fov, "
                                "vfov, size, width, height)")
            if any(c in text for c in ",:{}#\n"):
                raise ValueError(f"{where}: {text!r} (a name of letters, digits, '_' or '-')")
            items.append(f"{key}: {text}")
        lines.append("- {" + ", ".join(items) + "}")
    if not lines:
        raise ValueError("rig: no views (expected at least one mapping)")
    return "\n".join(lines) + "\n"


def job_of(images: Any, out_dir: Any, *, rig: Any, src: Optional[str], format: str, layout: str, quality: int,
           overwrite: bool) -> Dict[str, Any]:
    """The job's arguments as _core takes them, each checked for its Python type."""
    if isinstance(images, (str, os.PathLike)):
        inputs = [_staged.path_arg("images", images)]
    elif isinstance(images, Sequence):
        inputs = [_staged.path_arg(f"images[{i}]", v) for i, v in enumerate(images)]
    else:
        raise TypeError(f"images: {images!r} (expected a path or a sequence of paths)")
    if not isinstance(format, str):
        raise TypeError(f"format: {format!r} (expected 'jpg' or 'png')")
    if not isinstance(layout, str):
        raise TypeError(f"layout: {layout!r} (expected 'flat' or 'folders')")
    if isinstance(quality, bool) or not isinstance(quality, int):
        raise TypeError(f"quality: {quality!r} (expected an int)")
    if not 0 < quality <= 100:
        raise ValueError(f"quality: {quality} (expected 1 to 100)")
    return {"inputs": inputs, "output": _staged.path_arg("out_dir", out_dir), "src": src, "rig": rig_text(rig),
            "format": format, "layout": layout, "quality": quality, "overwrite": bool(overwrite)}
