"""The scale-out example: a folder of images through Dask's distributed scheduler (two worker
processes on this machine), one plan per worker."""
import os
import pathlib

import numpy as np

import panoproj as pp
from conftest import smooth_equirect

EXAMPLES = str(pathlib.Path(__file__).resolve().parents[1] / "examples")


def test_a_folder_converts_on_a_local_cluster(tmp_path, monkeypatch):
    # The workers import the example's task functions by name, as they would an installed module.
    monkeypatch.syspath_prepend(EXAMPLES)
    monkeypatch.setenv("PYTHONPATH", EXAMPLES + os.pathsep + os.environ.get("PYTHONPATH", ""))
    from dask.distributed import Client, LocalCluster

    import dask_convert_folder as example

    src, dst = tmp_path / "in", tmp_path / "out"
    src.mkdir()
    images = []
    for i in range(6):
        img = np.roll(smooth_equirect(512, 256), 40 * i, axis=1)
        pp.write(str(src / f"frame{i}.png"), img)
        images.append(img)
    plan = pp.Plan("equirect", "fisheye:fov=180", (512, 256), size=(128, 128), threads=1)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        written = example.convert_folder(client, plan, src, dst)
        # One plan object per worker process, unpickled once, reused by every task there.
        plans_per_worker = client.run(example.plans_held)
    assert len(written) == 6
    assert all(n == 1 for n in plans_per_worker.values())
    for i, img in enumerate(images):
        assert np.array_equal(pp.read(str(dst / f"frame{i}.png")), plan(img))
