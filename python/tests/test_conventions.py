"""Pixel conventions on to_ray, to_pixel and build_map: panoproj (centres at i + 0.5), opencv
(centres at i) and torch (grid_sample's [-1, 1] with align_corners=False)."""

import numpy as np
import pytest

import panoproj as pp

SIZE = (400, 200)


def test_to_ray_reads_each_convention():
    x, y = np.array([0.5, 123.25, 399.5]), np.array([0.5, 77.0, 199.5])
    rays, ok = pp.to_ray("equirect", SIZE, x, y)
    for convention, cx, cy in [("opencv", x - 0.5, y - 0.5), ("torch", 2 * x / 400 - 1, 2 * y / 200 - 1)]:
        r, k = pp.to_ray("equirect", SIZE, cx, cy, convention=convention)
        np.testing.assert_allclose(r, rays, atol=1e-12)
        assert (k == ok).all()


def test_to_pixel_gives_each_convention_and_round_trips():
    rng = np.random.default_rng(3)
    rays = rng.normal(size=(1000, 3))
    x, y, ok = pp.to_pixel("equirect", SIZE, rays)
    for convention, fx, fy in [("opencv", x - 0.5, y - 0.5), ("torch", 2 * x / 400 - 1, 2 * y / 200 - 1)]:
        cx, cy, k = pp.to_pixel("equirect", SIZE, rays, convention=convention)
        np.testing.assert_allclose(cx, fx, atol=1e-12)
        np.testing.assert_allclose(cy, fy, atol=1e-12)
        back, _ = pp.to_ray("equirect", SIZE, cx, cy, convention=convention)
        np.testing.assert_allclose(back, rays / np.linalg.norm(rays, axis=-1, keepdims=True), atol=1e-9)
    assert (np.abs(pp.to_pixel("equirect", SIZE, rays, convention="torch")[0]) <= 1).all()


def _grid_sample(img, grid):
    """torch.nn.functional.grid_sample(bilinear, zeros padding, align_corners=False) on HxW, in numpy."""
    h, w = img.shape
    x = (grid[..., 0] + 1) * w / 2 - 0.5
    y = (grid[..., 1] + 1) * h / 2 - 0.5
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    out = np.zeros(grid.shape[:-1])
    for dx in (0, 1):
        for dy in (0, 1):
            xi, yi = x0 + dx, y0 + dy
            wgt = (1 - abs(x - xi)) * (1 - abs(y - yi))
            inside = (xi >= 0) & (xi < w) & (yi >= 0) & (yi < h)
            out += np.where(inside, wgt * img[np.clip(yi, 0, h - 1), np.clip(xi, 0, w - 1)], 0)
    return out


def test_torch_grid_samples_like_the_opencv_maps():
    src = np.random.default_rng(5).random((200, 400)).astype(np.float32)
    grid = pp.build_map("equirect", "fisheye:fov=200", SIZE, size=(96, 96), convention="torch")
    mx, my = pp.build_map("equirect", "fisheye:fov=200", SIZE, size=(96, 96))
    assert grid.shape == (96, 96, 2) and grid.dtype == np.float32
    valid = mx >= 0
    np.testing.assert_allclose(grid[..., 0][valid], (2 * mx[valid] + 1) / 400 - 1, atol=1e-6)
    np.testing.assert_allclose(grid[..., 1][valid], (2 * my[valid] + 1) / 200 - 1, atol=1e-6)
    assert (grid[~valid] == -2).all()
    inner = valid & (mx > 1) & (mx < 398) & (my > 1) & (my < 198)
    ref = pp.convert(src, "equirect", "fisheye:fov=200", size=(96, 96), interp="bilinear", antialias="off")
    np.testing.assert_allclose(_grid_sample(src, grid)[inner], ref[inner], atol=2e-3)
    assert (_grid_sample(src, grid)[~valid] == 0).all()


def test_bad_convention_names_the_choices():
    with pytest.raises(ValueError, match="convention: 'OpenCV'"):
        pp.to_pixel("equirect", SIZE, [[0, 0, 1]], convention="OpenCV")
