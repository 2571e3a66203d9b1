"""pp.tiles: the pyramid in this process and on a Dask LocalCluster (two worker processes), byte
for byte the same; the report's counts against each viewer's rule. (The tiles' pixels against
direct renders: tests/tiles_test.cpp; the viewers themselves: scripts/tiles-oracle.sh.)"""
import hashlib
import json
import math
import pathlib

import numpy as np
import pytest

import panoproj as pp
from conftest import smooth_equirect


def digests(folder):
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(pathlib.Path(folder).rglob("*")) if p.is_file()}


@pytest.fixture(scope="module")
def pano(tmp_path_factory):
    path = tmp_path_factory.mktemp("tiles") / "pano.jpg"
    rng = np.random.default_rng(5)
    img = smooth_equirect(1024, 512).astype(np.int16) + rng.integers(-20, 20, (512, 1024, 3))
    pp.write(str(path), np.clip(img, 0, 255).astype(np.uint8), quality=92)
    return path


@pytest.mark.parametrize("viewer", ["pannellum", "marzipano"])
def test_tiles_on_a_local_cluster_equal_the_local_run(pano, tmp_path, viewer):
    from dask.distributed import Client, LocalCluster

    local = pp.tiles(pano, tmp_path / "local", viewer=viewer, tile=128)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        remote = pp.tiles(pano, tmp_path / "dask", viewer=viewer, tile=128, client=client, threads=1)
    assert remote["tasks"] > 6
    assert remote["written"] == local["written"] == local["tile_count"]
    assert digests(tmp_path / "dask") == digests(tmp_path / "local")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dask", "local"]  # no temporary folder left


def test_the_report_counts_every_levels_tiles(pano, tmp_path):
    r = pp.tiles(pano, tmp_path / "p", tile=128, format="png")
    cube = 8 * int(1024 / math.pi / 8)  # generate.py's
    assert r["levels"][-1]["size"] == cube and r["tile"] == 128
    assert r["tile_count"] == sum(6 * math.ceil(l["size"] / 128) ** 2 for l in r["levels"])
    config = json.loads((tmp_path / "p" / "config.json").read_text())
    assert config["multiRes"] == {"path": "/%l/%s%y_%x", "fallbackPath": "/fallback/%s", "extension": "png",
                                  "tileResolution": 128, "maxLevel": len(r["levels"]), "cubeResolution": cube}
    assert len(list((tmp_path / "p").rglob("*.png"))) == r["tile_count"] + 6  # and six fallback faces
