"""GoPro MAX strips on the real frames (samples/gopro_max/, scripts/gopro_max_figures.py):
  - the band repeats D px along each side seam (the layout's constant, measured);
  - seams: the blend never rougher across a seam than the hard cut, and no seam an outlier among
    the lines 120 px around it;
  - the 3K equirect against max2sphere's: closer at its quarter-pixel offset; the preset's band
    closer than bands 8 px off (a wrong layout is seen);
  - two strips as arrays equal the command's two files; bad pairs: one line, exit 1, nothing written."""
import pathlib
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

import panoproj

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "scripts"))
import gopro_max_figures as g  # noqa: E402

FRAMES = g.FRAMES


@pytest.mark.parametrize("mode", list(g.PAIRS))
def test_the_band_repeats_its_width_along_the_side_seams(mode):
    D = g.PAIRS[mode][4]
    found = g.band_repeat(mode)
    for seam in ("left", "right"):  # (the up face is sky, the down face the photographer)
        offsets = found[seam]["offsets"]
        assert np.median(offsets) == pytest.approx(D, abs=3), (mode, seam, found[seam])


@pytest.mark.parametrize("mode", list(g.PAIRS))
def test_the_blend_leaves_no_seam(cli, tmp_path, mode):
    a, b, S, C, D = g.PAIRS[mode]
    stats = {}
    for spec in ("gopro-max", "gopro-max:feather=0"):
        out = tmp_path / f"{spec.replace(':', '_')}.png"
        subprocess.run([cli, "convert", FRAMES / a, FRAMES / b, out, "--from", spec, "--to", "cubemap",
                        "--size", f"{6 * C}x{C}"], check=True, capture_output=True)
        stats[spec] = g.seam_statistics(out, C)
    for name, _, _ in g.CUBE_SEAMS:
        blended, cut = stats["gopro-max"][name], stats["gopro-max:feather=0"][name]
        assert blended["seam"] <= cut["seam"], (mode, name, blended, cut)
        assert blended["rank"] < 0.9, (mode, name, blended)


def test_the_3k_equirect_meets_max2sphere_at_its_quarter_pixel(cli, tmp_path):
    peer, _ = g.against_peer(cli, tmp_path)
    assert peer["shifted"]["overall"] > peer["as is"]["overall"] + 2
    assert peer["shifted"]["overall"] > peer["shifted the other way"]["overall"] + 2
    assert peer["shifted"]["overall"] > 34
    assert peer["shifted"]["seam bands"] > 34
    # A band 8 px off (a layout not the camera's) is further from the peer.
    a, b, S, C, D = g.PAIRS["3k"]
    reference = g.load(g.PEER_3K)
    for band in (D - 8, D + 8):
        out = tmp_path / f"band{band}.png"
        subprocess.run([cli, "convert", FRAMES / a, FRAMES / b, out, "--from", f"gopro-max:band={band}", "--to", "equirect",
                        "--size", "2272x1136"], check=True, capture_output=True)
        off = g.psnr(g.shifted(g.load(out), -0.25, 0.25)[2:-2, 2:-2], reference[2:-2, 2:-2])
        assert off < peer["shifted"]["overall"] - 0.5, (band, off)


def test_two_strips_as_arrays_equal_the_two_files(cli, tmp_path):
    a, b, S, C, D = g.PAIRS["3k"]
    strips = [np.asarray(Image.open(FRAMES / f)) for f in (a, b)]
    got = panoproj.convert(strips, "gopro-max", "equirect", size=(1136, 568))
    out = tmp_path / "pair.png"
    subprocess.run([cli, "convert", FRAMES / a, FRAMES / b, out, "--from", "gopro-max", "--to", "equirect", "--size",
                    "1136x568"], check=True, capture_output=True)
    assert np.array_equal(got, np.asarray(Image.open(out)))
    stacked = panoproj.convert(np.concatenate(strips, axis=0), "gopro-max", "equirect", size=(1136, 568))
    assert np.array_equal(got, stacked)
    with pytest.raises(ValueError, match="expected the two strips"):
        panoproj.convert(strips + strips[:1], "gopro-max", "equirect")
    with pytest.raises(ValueError, match="equal shapes"):
        panoproj.convert([strips[0], strips[1][:-2]], "gopro-max", "equirect")
    with pytest.raises(ValueError, match="match no preset"):
        panoproj.convert(np.zeros((100, 300, 3), np.uint8), "gopro-max", "equirect")


@pytest.mark.parametrize("inputs, message", [
    (("3k_track0_GS018423_1.jpg", "5_6k_track5_GS018421_1.jpg"), "expected one frame of each of the two streams"),
    (("3k_track0_GS018423_1.jpg", "missing_track5.jpg"), "missing_track5.jpg"),
    (("3k_track0_GS018423_1.jpg", "3k_track5_GS018423_1.jpg", "3k_track5_GS018423_1.jpg"), "3 inputs for --from"),
    (("3k_track0_GS018423_1.jpg",), "strips of 2272x368 match no preset"),
])
def test_bad_pairs_are_one_line_and_write_nothing(cli, tmp_path, inputs, message):
    out = tmp_path / "out.jpg"
    r = subprocess.run([cli, "convert", *[FRAMES / i for i in inputs], out, "--from", "gopro-max", "--to", "equirect"],
                       capture_output=True, text=True)
    assert r.returncode == 1, r.stderr
    assert message in r.stderr and r.stderr.count("\n") == 1, r.stderr
    assert not out.exists() and list(tmp_path.iterdir()) == []
