"""The blended panorama (stitch project.pto pano.jpg): its weights sum to 1 wherever an image
covers, hold still from frame to frame (they come from the geometry alone: the output is linear in
the images), a pixel one layer covers is that layer's, bands give the panorama whole; against the
truth of a real panorama cut into views and enblend (a test oracle) on the same layers."""
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import panoproj as pp

ROOT = Path(__file__).resolve().parents[2]
CLI = os.environ.get("PANOPROJ_CLI", str(ROOT / "build/tools/panoproj"))
JORDAN = ROOT / "samples/images/jordan_pond_4096x2048.jpg"
# (lens type, yaw, pitch, roll, hfov): five lens types round the sphere.
VIEWS = [(0, 0, 0, 0, 100), (3, 90, 20, 5, 160), (21, 180, -10, -3, 170), (10, 270, 5, 2, 160),
         (0, 45, 60, 0, 100), (8, 225, -60, 10, 160), (3, 0, 89, 0, 150), (21, 0, -89, 0, 150)]
LENSES = {0: "rectilinear", 3: "equidistant", 8: "orthographic", 10: "stereographic", 21: "equisolid"}
BLENDS = [{}, {"blend": "multiband"}]


def views_project(d: Path, width: int, views=VIEWS):
    """The views of the real Jordan Pond panorama (at `width`) through their lenses, as a project;
    returns it and the source."""
    step = 4096 // width
    src = np.ascontiguousarray(pp.read(str(JORDAN))[::step, ::step])
    lines = [f'p f2 w{width} h{width // 2} v360 E0 R0 n"TIFF_m c:NONE r:CROP"\nm i5\n']
    for k, (f, yaw, pitch, roll, v) in enumerate(views):
        view = pp.convert(src, "equirect", f"panotools:lens={LENSES[f]},hfov={v}", yaw=yaw, pitch=pitch,
                          roll=roll, interp="bicubic")
        pp.write(str(d / f"v{k}.png"), view)
        lines.append(f'i w{view.shape[1]} h{view.shape[0]} f{f} v{v} r{roll} p{pitch} y{yaw} n"v{k}.png"\n')
    (d / "views.pto").write_text("".join(lines))
    return d / "views.pto", src


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    d = tmp_path_factory.mktemp("blend")
    project, src = views_project(d, 512)
    return d, project, src


def coverage(project, **kw):
    """How many layers cover each pixel of the canvas."""
    got = pp.stitch_layers(str(project), **kw)
    count = np.zeros(got.canvas[::-1], np.int32)
    for layer in got.layers:
        x, y = layer.offset
        h, w = layer.pixels.shape[:2]
        count[y:y + h, x:x + w] += layer.pixels[..., -1] > 0
    return count, got


def constant_images(d: Path, project: Path, value, name="c"):
    """Files of each view's size holding `value` (a list: one per view), in project order."""
    files = []
    for k, v in enumerate(value):
        shape = pp.read(str(d / f"v{k}.png")).shape
        files.append(str(d / f"{name}{k}.tif"))
        pp.write(files[-1], np.full(shape, v, np.float32), overwrite=True)
    return files


@pytest.mark.parametrize("blend", BLENDS, ids=["feather", "multiband"])
def test_weights_sum_to_one_wherever_an_image_covers(small, blend):
    d, project, _ = small
    files = constant_images(d, project, [0.5] * len(VIEWS))
    pano = pp.stitch_panorama(str(project), images=files, **blend)
    count, _ = coverage(project)
    covered = pano[..., 3] > 0
    assert np.array_equal(covered, count > 0)
    # Weights summing to s give 0.5 s: within 1e-6 of 0.5 everywhere covered (multiband: at every
    # level), and overlaps of up to len(VIEWS) layers are there.
    assert count.max() >= 3
    assert np.abs(pano[covered][:, :3] - 0.5).max() < 1e-6
    assert not pano[~covered].any()


def test_no_layer_ends_where_it_still_weighs(small):
    """Each view a constant of its own (0.1 to 0.8): the feather's panorama has no step between
    neighbouring pixels, so no layer's alpha ends where its weight is not ~0 (an orthographic
    view's pixels end at 90 degrees, inside its frame: its margin ends there too)."""
    d, project, _ = small
    files = constant_images(d, project, [0.1 + 0.1 * k for k in range(len(VIEWS))], name="steps")
    pano = pp.stitch_panorama(str(project), images=files).astype(np.float64)
    steps = []
    for axis in (0, 1):  # (down, and across the 360-degree seam too)
        a = pano[..., 3] > 0
        both = a & np.roll(a, -1, axis)
        if axis == 0:
            both[-1] = False  # (the bottom row's neighbour is not the top row)
        steps.append(np.abs(pano[..., 0] - np.roll(pano[..., 0], -1, axis))[both].max())
    # (Ramps as narrow as their overlap: a few pixels where two fields only graze.)
    print(f"largest step between neighbours: {max(steps):.4f} (the views differ by up to 0.7)")
    assert max(steps) < 0.06


@pytest.mark.parametrize("blend", BLENDS, ids=["feather", "multiband"])
def test_weights_hold_still_over_30_frames(small, blend):
    """Thirty frames of the scene, each image at its own flickering gain: each frame's panorama is
    the base frame's plus each image's own contribution at its gain step (found once, from one
    image's step alone). Weights that followed the content (enblend's seams) could not do that."""
    d, project, _ = small
    n = len(VIEWS)
    views = [pp.read(str(d / f"v{k}.png")).astype(np.float32) / 255 for k in range(n)]

    def render(gains, name):
        files = []
        for j in range(n):
            files.append(str(d / f"{name}_{j}.tif"))
            # (Lifted off 0 and 1: multiband's overshoot, clamped there, would not be linear.)
            pp.write(files[-1], (0.1 + 0.8 * views[j] * gains[j]).astype(np.float32), overwrite=True)
        return pp.stitch_panorama(str(project), images=files, **blend)[..., :3].astype(np.float64)

    base_gain, step = 0.8, 0.2
    base = render([base_gain] * n, "base")
    own = [(render([base_gain + (step if j == k else 0) for j in range(n)], "step") - base) / step
           for k in range(n)]
    rng = np.random.default_rng(7)
    worst = 0.0
    for f in range(30):
        gains = rng.uniform(0.6, 1.0, n)
        expected = base + sum((g - base_gain) * c for g, c in zip(gains, own))
        worst = max(worst, float(np.abs(render(gains, "frame") - expected).max()))
    print(f"{blend or 'feather'}: 30 frames against the images' own contributions: {worst:.2e}")
    assert worst < 1e-5


@pytest.fixture(scope="module")
def row_of_three(tmp_path_factory):
    """Three rectilinear views 50 degrees apart: overlaps between neighbours only."""
    d = tmp_path_factory.mktemp("three")
    project, src = views_project(d, 1024, views=[(0, yaw, 0, 0, 70) for yaw in (0, 50, 100)])
    return d, project, src


@pytest.mark.parametrize("blend", BLENDS, ids=["feather", "multiband"])
def test_a_pixel_one_layer_covers_is_that_layers(row_of_three, blend):
    d, project, _ = row_of_three
    levels = 2 if blend else 0
    pano = pp.stitch_panorama(str(project), **blend, levels=levels or None)
    count, layers = coverage(project)
    # Multiband: where no other layer lies within its pyramids' reach (4 x 2^levels pixels).
    reach = 4 * 2 ** levels if levels else 0
    checked = 0
    for layer in layers.layers:
        x, y = layer.offset
        h, w = layer.pixels.shape[:2]
        alone = (count[y:y + h, x:x + w] == 1) & (layer.pixels[..., 3] > 0)
        if reach:
            others = (count[y:y + h, x:x + w] - (layer.pixels[..., 3] > 0)) > 0
            near = np.zeros_like(others)
            for dy in range(-reach, reach + 1, max(1, reach // 8)):
                for dx in range(-reach, reach + 1, max(1, reach // 8)):
                    near |= np.roll(np.roll(others, dy, 0), dx, 1)
            alone &= ~near
        checked += alone.sum()
        diff = np.abs(pano[y:y + h, x:x + w][alone].astype(int) - layer.pixels[alone].astype(int))
        assert diff.max(initial=0) <= (1 if reach else 0), layer.image
    assert checked > 1000


@pytest.mark.parametrize("blend", BLENDS, ids=["feather", "multiband"])
def test_bands_give_the_panorama_whole(small, blend):
    d, project, _ = small
    whole = pp.stitch_panorama(str(project), **blend, levels=3 if blend else None)
    banded = pp.stitch_panorama(str(project), **blend, levels=3 if blend else None,
                                memory_limit="40M" if not blend else "48M")
    diff = np.abs(whole.astype(int) - banded.astype(int))
    # (Each band's layers sampled through its own tile maps: positions within 1/1024 px.)
    assert diff.max() <= 1 and (diff > 0).mean() < 1e-4


def test_the_panorama_file_is_the_array_with_photo_sphere_metadata(small):
    d, project, _ = small
    subprocess.run([CLI, "stitch", str(project), str(d / "p.png"), "--overwrite", "--quiet"], check=True)
    assert np.array_equal(pp.read(str(d / "p.png")), pp.stitch_panorama(str(project)))
    subprocess.run([CLI, "stitch", str(project), str(d / "p.jpg"), "--overwrite", "--quiet"], check=True)
    _, meta = pp.read(str(d / "p.jpg"), metadata=True)
    assert meta["GPano:FullPanoWidthPixels"] == 512 and meta["GPano:ProjectionType"] == "equirectangular"
    assert pp.read(str(d / "p.jpg")).shape == (256, 512, 3)


@pytest.mark.skipif(shutil.which("enblend") is None, reason="enblend is not installed")
def test_against_the_truth_beside_enblend(tmp_path):
    """The views put back, against the panorama they were cut from, in the overlaps (two layers
    or more): panoproj's feather and multiband beside enblend on the same layers."""
    project, src = views_project(tmp_path, 2048)
    count, _ = coverage(project)
    overlap = count >= 2
    subprocess.run([CLI, "stitch", str(project), str(tmp_path / "l_"), "--quiet"], check=True)
    subprocess.run(["enblend", "-o", str(tmp_path / "enblend.tif"), *sorted(map(str, tmp_path.glob("l_*.tif")))],
                   check=True, capture_output=True)
    enblend = pp.read(str(tmp_path / "enblend.tif"))
    # enblend's output is the layers' union's bounding box (here the canvas).
    assert enblend.shape[:2] == src.shape[:2]
    results = {"enblend": enblend[..., :3]}
    for name, blend in (("feather", {}), ("multiband", {"blend": "multiband"})):
        results[name] = pp.stitch_panorama(str(project), **blend)[..., :3]

    def psnr(a):
        e = np.mean((a[overlap].astype(np.float64) - src[overlap]) ** 2)
        return 10 * np.log10(255 ** 2 / e)

    got = {k: psnr(v) for k, v in results.items()}
    print("PSNR in the overlaps (%.0f%% of the canvas): " % (100 * overlap.mean()) +
          ", ".join(f"{k} {v:.2f} dB" for k, v in got.items()))
    assert got["feather"] > got["enblend"] - 0.5
    assert got["multiband"] > got["enblend"] - 0.5
    # The deliberate mistake: the views averaged with equal weights (no feather) is worse.
    layers = pp.stitch_layers(str(project))
    total, weight = np.zeros(src.shape, np.float64), np.zeros(src.shape[:2])
    for layer in layers.layers:
        x, y = layer.offset
        h, w = layer.pixels.shape[:2]
        a = layer.pixels[..., 3] > 0
        total[y:y + h, x:x + w][a] += layer.pixels[..., :3][a]
        weight[y:y + h, x:x + w][a] += 1
    mean = total / np.maximum(weight, 1)[..., None]
    assert psnr(mean) < got["feather"]
