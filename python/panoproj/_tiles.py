"""Multires tile pyramids for Pannellum and Marzipano (the command's ``panoproj tiles``), locally
or on a Dask ``distributed`` client: the client begins the job (checks, a temporary folder beside
the output), each task renders bands of tile rows into it reading only the source region and
scale they need, and the client finishes (preview, config, index.html) and lands the folder.
The bytes equal a local run's: each tile depends only on the job."""
from __future__ import annotations

import time
from typing import Any, Dict, Optional, Sequence, Tuple

from . import _core, _staged
from ._staged import Staged

Rows = Tuple[int, int, int, int]  # (level index, face, first row, end row)


def render_rows(job: Dict[str, Any], options: Dict[str, Any], folder: Staged, rows: Sequence[Rows]) -> Tuple[int, int]:
    """One task: the tiles of ``rows`` written into ``folder``; returns (written, empty)."""
    written, empty = _core.tiles_render(job, options, folder, list(rows))
    return int(written), int(empty)


def run(job: Dict[str, Any], options: Dict[str, Any], client: Any = None,
        band_pixels: int = 1 << 24) -> Dict[str, Any]:
    """The whole pyramid: in this process, or as tasks on ``client`` (a dask.distributed Client)."""
    if client is None:
        return dict(_core.tiles(job, options))
    t0 = time.perf_counter()
    folder, work = _core.tiles_begin(job, options, band_pixels)
    return _staged.run_on_client(client, render_rows, job, options, folder, [[rows] for rows in work],
                                 _core.tiles_finish, _core.tiles_abandon, t0)


def job_of(image: Any, out_dir: Any, *, viewer: str, src: Optional[str], tile: int, levels: Optional[int],
           cube_size: Optional[int], format: str, quality: int, preview: Optional[int], script_url: Optional[str],
           overwrite: bool) -> Dict[str, Any]:
    """The job's arguments as _core takes them, each checked for its Python type."""
    def integer(name: str, v: Any, none: int) -> int:
        if v is None:
            return none
        if isinstance(v, bool) or not isinstance(v, int):
            raise TypeError(f"{name}: {v!r} (expected an int)")
        if not -(1 << 62) < v < (1 << 62):
            raise ValueError(f"{name}: {v} is out of range")
        return v

    def text(name: str, v: Any, none: str) -> str:
        if v is None:
            return none
        if not isinstance(v, str):
            raise TypeError(f"{name}: {v!r} (expected a str)")
        return v

    return {"input": _staged.path_arg("image", image), "output": _staged.path_arg("out_dir", out_dir), "src": src,
            "viewer": text("viewer", viewer, "pannellum"), "tile": integer("tile", tile, 512),
            "levels": integer("levels", levels, 0), "cube_size": integer("cube_size", cube_size, 0),
            "format": text("format", format, "jpg"), "quality": integer("quality", quality, 95),
            "preview": integer("preview", preview, 0), "script_url": text("script_url", script_url, ""),
            "overwrite": bool(overwrite)}
