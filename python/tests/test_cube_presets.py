"""Cube presets for engines (preset=threejs, preset=unity) against an oracle built from published
facts only, not from panoproj's face table:

- the cube-map face table (OpenGL 4.6 table 8.19; Direct3D's is the same): for a lookup vector r,
  the target of its major axis and the face coordinates (sc, tc), image column along s, row along
  t (row 0 first);
- three.js: a CubeTexture is looked up at (-x, y, z) (flipEnvMap; its docs: "px is the face
  towards -X"); its equirect texture maps a direction d to u = atan2(dz, dx) / 2pi + 1/2,
  v = asin(dy) / pi + 1/2 (equirectUv), v up;
- Unity: left-handed, looked up as is; Skybox/Panoramic maps d to u = 1/2 - atan2(dz, dx) / 2pi,
  v = 1 - acos(dy) / pi (ToRadialCoords), v up.

An equirect holding a smooth function of the engine's direction, converted by panoproj to the
preset's cube, must show on every target what the engine would look up there.
"""
import subprocess

import numpy as np
import pytest

import panoproj as pp

N = 48            # face size
W, H = 2048, 1024  # equirect

# Target k of +X -X +Y -Y +Z -Z: r = ma * axis + sc * s_axis + tc * t_axis (the table read backwards).
GL_TABLE = [
    ((1, 0, 0), (0, 0, -1), (0, -1, 0)),
    ((-1, 0, 0), (0, 0, 1), (0, -1, 0)),
    ((0, 1, 0), (1, 0, 0), (0, 0, 1)),
    ((0, -1, 0), (1, 0, 0), (0, 0, -1)),
    ((0, 0, 1), (1, 0, 0), (0, -1, 0)),
    ((0, 0, -1), (-1, 0, 0), (0, -1, 0)),
]


def lookup_vectors(k: int) -> np.ndarray:
    """The lookup vector r at each pixel centre of target k (N x N x 3)."""
    major, s_axis, t_axis = (np.array(v, float) for v in GL_TABLE[k])
    c = (np.arange(N) + 0.5) / N * 2 - 1
    tc, sc = np.meshgrid(c, c, indexing="ij")
    return major + sc[..., None] * s_axis + tc[..., None] * t_axis


ENGINES = {
    # lookup vector -> world direction; world direction -> (u, v) of the equirect, v up
    "threejs": (lambda r: r * np.array([-1.0, 1.0, 1.0]),
                lambda d: (np.arctan2(d[..., 2], d[..., 0]) / (2 * np.pi) + 0.5,
                           np.arcsin(np.clip(d[..., 1], -1, 1)) / np.pi + 0.5)),
    "unity": (lambda r: r,
              lambda d: (0.5 - np.arctan2(d[..., 2], d[..., 0]) / (2 * np.pi),
                         1 - np.arccos(np.clip(d[..., 1], -1, 1)) / np.pi)),
}


def scene(d: np.ndarray) -> np.ndarray:
    d = d / np.linalg.norm(d, axis=-1, keepdims=True)
    return (0.5 + 0.4 * d).astype(np.float32)


def engine_equirect(engine: str) -> np.ndarray:
    """The equirect whose pixel (u, v) the engine shows at direction d holds scene(d)."""
    _, uv = ENGINES[engine]
    u = (np.arange(W) + 0.5) / W
    v = 1 - (np.arange(H) + 0.5) / H
    vv, uu = np.meshgrid(v, u, indexing="ij")
    # The lookup inverted (both are longitude and latitude), then checked by the lookup itself.
    if engine == "threejs":
        lon, lat = (uu - 0.5) * 2 * np.pi, (vv - 0.5) * np.pi
    else:
        lon, lat = (0.5 - uu) * 2 * np.pi, np.pi / 2 - (1 - vv) * np.pi
    d = np.stack([np.cos(lat) * np.cos(lon), np.sin(lat), np.cos(lat) * np.sin(lon)], axis=-1)
    back = uv(d)  # the engine's own lookup must return the pixel it came from
    assert np.allclose(back[0] % 1, uu % 1, atol=1e-9) and np.allclose(back[1], vv, atol=1e-9)
    return scene(d)


def expected_targets(engine: str) -> list:
    to_world, _ = ENGINES[engine]
    return [scene(to_world(lookup_vectors(k))) for k in range(6)]


@pytest.mark.parametrize("engine", ["threejs", "unity"])
def test_preset_shows_what_the_engine_looks_up(engine):
    strip = pp.convert(engine_equirect(engine), "equirect", f"cubemap:preset={engine}",
                       size=(6 * N, N), interp="bilinear", antialias="off")
    want = expected_targets(engine)
    for k in range(6):
        err = np.abs(strip[:, k * N:(k + 1) * N] - want[k]).max()
        assert err < 1e-4, f"{engine} target {k}: {err}"


@pytest.mark.parametrize("engine", ["threejs", "unity"])
def test_a_wrong_turn_or_order_fails_the_oracle(engine):
    """The oracle tells a turned or swapped face: the preset's rows with one face turned or two
    faces swapped miss by far more than the bound."""
    order, rot = {"threejs": ("bfudrl", "001300"), "unity": ("fbudlr", "003100")}[engine]
    want = expected_targets(engine)
    for spec in (f"order={order},rot=001200" if engine == "threejs" else f"order={order},rot=001300",
                 f"order={order[1] + order[0] + order[2:]},rot={rot}"):
        strip = pp.convert(engine_equirect(engine), "equirect", f"cubemap:{spec}",
                           size=(6 * N, N), interp="bilinear", antialias="off")
        worst = max(np.abs(strip[:, k * N:(k + 1) * N] - want[k]).max() for k in range(6))
        assert worst > 0.1, spec
    strip = pp.convert(engine_equirect(engine), "equirect", f"cubemap:order={order},rot={rot}",
                       size=(6 * N, N), interp="bilinear", antialias="off")
    assert np.array_equal(strip, pp.convert(engine_equirect(engine), "equirect", f"cubemap:preset={engine}",
                                            size=(6 * N, N), interp="bilinear", antialias="off"))


def test_axis_names_files(tmp_path, cli):
    """preset=threejs with {axis}: px.png .. nz.png hold the targets +X .. -Z; without a preset
    {axis} names panoproj's own frame (front pz, right px, up ny) and reads back the same cube."""
    src = tmp_path / "e.exr"
    pp.write(str(src), engine_equirect("threejs"))
    subprocess.run([cli, "convert", str(src), str(tmp_path / "{axis}.exr"), "--to",
                    "cubemap:layout=files,preset=threejs", "--size", f"{N}x{N}", "--interp", "bilinear",
                    "--antialias", "off"], check=True, capture_output=True)
    want = expected_targets("threejs")
    for k, name in enumerate(["px", "nx", "py", "ny", "pz", "nz"]):
        got = pp.read(str(tmp_path / f"{name}.exr"))[..., :3]
        assert np.abs(got - want[k]).max() < 1e-4, name
    # Without a preset: panoproj's frame, slot k face k (front pz, up ny); read back in that order.
    mine = tmp_path / "mine"
    mine.mkdir()
    subprocess.run([cli, "convert", str(src), str(mine / "{axis}.exr"), "--to", "cubemap:layout=files",
                    "--size", f"{N}x{N}", "--interp", "bilinear", "--antialias", "off"],
                   check=True, capture_output=True)
    strip = pp.convert(pp.read(str(src)), "equirect", "cubemap", size=(6 * N, N), interp="bilinear",
                       antialias="off")
    assert np.array_equal(strip[:, :N], pp.read(str(mine / "pz.exr"))[..., :3])
    assert np.array_equal(strip[:, 4 * N:5 * N], pp.read(str(mine / "ny.exr"))[..., :3])
    assert np.array_equal(pp.read(str(mine / "{axis}.exr"))[..., :3], strip)


@pytest.mark.parametrize("spec, words", [
    ("cubemap:preset=threejs,order=frblud", "drop order and rot"),
    ("cubemap:preset=unity,rot=000000", "drop order and rot"),
    ("cubemap:layout=eac,preset=unity", "drop layout=eac"),
    ("cubemap:preset=babylon", "preset"),
])
def test_bad_presets(spec, words):
    with pytest.raises(ValueError, match=words):
        pp.convert(np.zeros((8, 16, 3), np.float32), "equirect", spec, size=(48, 8))
