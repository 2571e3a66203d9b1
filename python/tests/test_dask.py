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


def test_a_video_converts_in_parts_on_a_local_cluster_and_joins_into_the_whole(tmp_path, monkeypatch):
    # A 2 s FFV1 clip with a keyframe every 10 frames, cut into 3 parts between keyframes: the
    # joined parts have every frame of the whole conversion once, bit for bit, at its times.
    import shutil
    import subprocess

    if not shutil.which("ffmpeg"):
        import pytest
        pytest.skip("ffmpeg (a test oracle) is not installed")
    monkeypatch.syspath_prepend(EXAMPLES)
    monkeypatch.setenv("PYTHONPATH", EXAMPLES + os.pathsep + os.environ.get("PYTHONPATH", ""))
    from dask.distributed import Client, LocalCluster

    import dask_convert_video as example

    src = tmp_path / "clip.mkv"
    subprocess.run(["ffmpeg", "-v", "error", "-f", "lavfi", "-i", "testsrc2=size=256x128:rate=24:duration=2",
                    "-c:v", "ffv1", "-g", "10", "-pix_fmt", "yuv420p", str(src)], check=True)
    more = ["--size", "192x128", "--codec", "ffv1"]
    whole = tmp_path / "whole.mkv"
    example.convert_part(src, whole, 0.0, None, "cubemap:layout=3x2", more)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        joined = example.convert_video(client, src, tmp_path / "joined.mkv", "cubemap:layout=3x2", 3, more)

    def frames(path):  # (pts, hash) of each decoded frame
        out = subprocess.run(["ffmpeg", "-v", "error", "-i", str(path), "-map", "0:v", "-f", "framemd5", "-"],
                             check=True, capture_output=True, text=True).stdout
        rows = [line.split(",") for line in out.splitlines() if not line.startswith("#")]
        return [(int(r[2]), r[-1].strip()) for r in rows]

    assert len(frames(whole)) == 48
    assert frames(joined) == frames(whole)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["clip.mkv", "joined.mkv", "whole.mkv"]
