"""Folder jobs (pp.tiles, pp.views): their path arguments checked, and their run on a Dask
``distributed`` client: the caller has begun the job (a temporary folder beside the output);
each item is a task that writes its files into the folder and returns (written, empty); the
counts' sums finish the job (the folder lands), and any failure abandons it (the folder
removed)."""
from __future__ import annotations

import os
import time
from typing import Any, Callable, Dict, List, Sequence, Tuple

# The temporary folder as the tasks carry it: (path, device, inode); each task refuses a folder
# of another identity (one swapped in meanwhile).
Staged = Tuple[str, int, int]


def path_arg(name: str, v: Any) -> str:
    """A path argument as the core takes it: a str, or an os.PathLike giving one."""
    try:
        p = os.fspath(v)
    except TypeError:
        raise TypeError(f"{name}: {v!r} (expected a str or os.PathLike path)") from None
    if not isinstance(p, str):
        raise TypeError(f"{name}: {v!r} (expected a str or os.PathLike path)")
    return p


def run_on_client(client: Any, task: Callable[..., Tuple[int, int]], job: Dict[str, Any], options: Dict[str, Any],
                  folder: Staged, items: Sequence[Any], finish: Callable[..., Any],
                  abandon: Callable[[Staged], None], t0: float) -> Dict[str, Any]:
    """task(job, options, folder, item) per item on the client; finish(job, options, folder,
    [written, empty]) then; t0: when the job began (perf_counter)."""
    try:
        futures = [client.submit(task, job, options, folder, item, pure=False) for item in items]
        counts: List[Tuple[int, int]] = client.gather(futures)
        report = dict(finish(job, options, folder, [sum(c[0] for c in counts), sum(c[1] for c in counts)]))
    except BaseException:
        abandon(folder)
        raise
    report["seconds"] = time.perf_counter() - t0
    report["tasks"] = len(futures)
    return report
