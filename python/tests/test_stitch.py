"""Hugin projects against Hugin's own remapper, nona (apt's hugin-tools, a test oracle): every lens
type and every panorama projection panoproj renders, with the polynomial a b c, shift d e, shear
g t and crops non-zero, both sides bilinear (the project's m i5) without antialiasing. Each layer:
its offset and size identical, alpha boundaries within 1 px, PSNR inside the common alpha eroded
by 1 px at least 45 dB (about 75 dB measured: 8-bit rounding; 95 dB in float). Then masks of every
type, enblend taking the layers unchanged, the truth of a real panorama cut into views and put
back, and Python's arrays.
"""
import os
import shutil
import struct
import subprocess
from pathlib import Path

import numpy as np
import pytest

import panoproj as pp

OpenImageIO = pytest.importorskip("OpenImageIO")
ROOT = Path(__file__).resolve().parents[2]
CLI = os.environ.get("PANOPROJ_CLI", str(ROOT / "build/tools/panoproj"))
JORDAN = ROOT / "samples/images/jordan_pond_4096x2048.jpg"
needs_nona = pytest.mark.skipif(shutil.which("nona") is None, reason="nona (hugin-tools) is not installed")

# The lens types and the fields they are tried at (Thoby's law folds at 126 degrees off axis:
# nona maps rays past the fold back into the image, panoproj gives them no source; 140 keeps
# the image's corners inside the fold).
LENSES = [(0, 70), (1, 100), (2, 180), (3, 150), (4, 120), (8, 160), (10, 170), (20, 140), (21, 170)]
PANOS = [(0, 120), (1, 200), (2, 360), (3, 200), (4, 200), (5, 300), (6, 120), (7, 360), (8, 360), (9, 300),
         (11, 360), (14, 180), (15, 300), (19, 200), (20, 200), (21, 360)]
DIST = "a0.01 b-0.03 c0.012 d9.5 e-6.25 g4 t-3"
PHOTOMETRY = "Ra0 Rb0 Rc0 Rd0 Re0 Eev0 Er1 Eb1 Va1 Vb0 Vc0 Vd0 Vx0 Vy0 Vm5"


@pytest.fixture(scope="module")
def photo(tmp_path_factory):
    """A 600x400 photo (a crop of the real Jordan Pond panorama)."""
    d = tmp_path_factory.mktemp("stitch")
    pixels = pp.read(str(JORDAN))[700:1100, 1500:2100]
    pp.write(str(d / "img.png"), np.ascontiguousarray(pixels))
    return d


def image_line(f, v, ypr=(20, 10, 5), dist=DIST, extra="", name="img.png", size=(600, 400)):
    y, p, r = ypr
    return (f"i w{size[0]} h{size[1]} f{f} v{v} {PHOTOMETRY} r{r} p{p} y{y} TrX0 TrY0 TrZ0 Tpy0 Tpp0 {dist} "
            f"{extra} n\"{name}\"\n")


def pano_line(f=2, v=360, w=800, h=400, extra="", output="TIFF_m c:NONE r:CROP"):
    return f"p f{f} w{w} h{h} v{v} E0 R0 {extra} n\"{output}\"\nm i5\n"


def tiff_tags(path):
    """The first IFD's tags of a TIFF: {tag: (type, values)}, rationals as floats."""
    data = Path(path).read_bytes()
    e = "<" if data[:2] == b"II" else ">"
    sizes = {1: 1, 2: 1, 3: 2, 4: 4, 5: 8, 11: 4, 12: 8}
    codes = {1: "B", 2: "c", 3: "H", 4: "I", 11: "f", 12: "d"}
    ifd = struct.unpack(e + "I", data[4:8])[0]
    tags = {}
    for k in range(struct.unpack(e + "H", data[ifd:ifd + 2])[0]):
        tag, typ, count, value = struct.unpack(e + "HHI4s", data[ifd + 2 + 12 * k:ifd + 14 + 12 * k])
        size = sizes[typ] * count
        raw = value[:size] if size <= 4 else data[struct.unpack(e + "I", value)[0]:][:size]
        if typ == 5:
            pairs = struct.unpack(e + "%dI" % (2 * count), raw)
            tags[tag] = (typ, [pairs[i] / pairs[i + 1] for i in range(0, len(pairs), 2)])
        else:
            tags[tag] = (typ, list(struct.unpack(e + codes[typ] * count, raw)))
    return tags


def read_layer(path):
    """A layer's pixels (float, unit range), its offset (XPOSITION x XRESOLUTION, rounded) and
    its canvas (PIXAR_IMAGEFULLWIDTH, ...LENGTH)."""
    inp = OpenImageIO.ImageInput.open(str(path))
    spec = inp.spec()
    pixels = inp.read_image("float")
    inp.close()
    t = tiff_tags(path)
    at = lambda tag: t[tag][1][0] if tag in t else 0  # noqa: E731
    offset = (round(at(286) * at(282)), round(at(287) * at(283)))
    canvas = (at(33300), at(33301)) if 33300 in t else (spec.width, spec.height)
    return pixels, offset, canvas, spec


def on_canvas(path):
    pixels, (x, y), (w, h), _ = read_layer(path)
    c = np.zeros((h, w, pixels.shape[2]))
    c[y:y + pixels.shape[0], x:x + pixels.shape[1]] = pixels
    return c, (x, y, pixels.shape[1], pixels.shape[0])


def grow(m):
    """m and its 8 neighbours."""
    g = m.copy()
    g[1:] |= m[:-1]
    g[:-1] |= m[1:]
    g2 = g.copy()
    g2[:, 1:] |= g[:, :-1]
    g2[:, :-1] |= g[:, 1:]
    return g2


def erode(m):
    return ~grow(~m)


def render_both(d: Path, pto: str, nona_args=(), args=()):
    project = d / "t.pto"
    project.write_text(pto)
    for f in d.glob("[nq]_*.tif"):
        f.unlink()
    subprocess.run(["nona", *nona_args, "-m", "TIFF_m", "-o", str(d / "n_"), str(project)], check=True,
                   capture_output=True)
    subprocess.run([CLI, "stitch", str(project), str(d / "q_"), "--quiet", *args], check=True)
    ns, qs = sorted(d.glob("n_*.tif")), sorted(d.glob("q_*.tif"))
    assert [p.name[2:] for p in ns] == [p.name[2:] for p in qs]
    return list(zip(ns, qs))


def compare(pair, peak=1.0):
    """PSNR in the common alpha eroded by 1 px, pixels of either alpha farther than 1 px from the
    other's, and the layers' rectangles."""
    (a, ra), (b, rb) = on_canvas(pair[0]), on_canvas(pair[1])
    ma, mb = a[..., -1] > 0, b[..., -1] > 0
    far = int(((ma & ~grow(mb)) | (mb & ~grow(ma))).sum())
    common = erode(ma & mb)
    d = a[common][:, :-1] - b[common][:, :-1]
    mse = float(np.mean(d ** 2))
    psnr = 10 * np.log10(peak ** 2 / mse) if mse > 0 else 999.0
    return psnr, far, ra, rb, int(common.sum())


def check(pairs, floor=45.0):
    for pair in pairs:
        psnr, far, ra, rb, n = compare(pair)
        print(f"{pair[0].name}: {psnr:.1f} dB over {n} px, {far} px of alpha beyond 1 px, rect {ra}")
        assert ra == rb, (ra, rb)
        assert n > 1000
        assert far == 0
        assert psnr >= floor


@needs_nona
@pytest.mark.parametrize("f,v", LENSES)
def test_every_lens_type_matches_nona(photo, f, v):
    crop = "S100,500,10,390" if f == 2 else "S20,570,15,380"
    check(render_both(photo, pano_line() + image_line(f, v, extra=crop)))


@needs_nona
@pytest.mark.parametrize("f,v", PANOS)
def test_every_panorama_projection_matches_nona(photo, f, v):
    pto = pano_line(f, v, 600, 300) + image_line(3, 150, ypr=(-15, 5, 3)) + image_line(0, 70, ypr=(40, -10, -4))
    check(render_both(photo, pto))


@needs_nona
def test_float_layers_match_nona_to_95_db(photo):
    pairs = render_both(photo, pano_line() + image_line(0, 70, extra="S20,570,15,380"), ["-p", "FLOAT"],
                        ["--depth", "float"])
    assert read_layer(pairs[0][1])[3].format == OpenImageIO.FLOAT
    for n, q in pairs:  # the tags nona writes, as nona writes them
        tn, tq = tiff_tags(n), tiff_tags(q)
        for tag in (258, 262, 277, 282, 283, 296, 338, 339, 33300, 33301):
            assert tn[tag][1] == tq[tag][1], tag
        assert tq[338][1] == [2]  # unassociated alpha
    check(pairs, floor=85.0)


MASKS = {
    "exclude": image_line(0, 70, (0, 0, 0), extra="j0") + 'k i0 t0 p"100 100 300 80 250 300 120 250"\n',
    "include": image_line(0, 70, (0, 0, 0), extra="j0") + image_line(0, 70, (40, 0, 0), extra="j1")
    + 'k i1 t1 p"0 0 200 0 200 400 0 400"\n',
    "exclude-stack": image_line(0, 70, (0, 0, 0), extra="j0") + image_line(0, 70, (0, 0, 0), extra="j=0")
    + 'k i0 t2 p"100 100 300 80 250 300"\n',
    "include-stack": image_line(0, 70, (0, 0, 0), extra="j0") + image_line(0, 70, (0, 0, 0), extra="j=0")
    + image_line(0, 70, (30, 0, 0), extra="j2") + 'k i0 t3 p"300 0 600 0 600 400 300 400"\n',
    "exclude-lens": image_line(0, 70, (0, 0, 0), extra="j0")
    + image_line(0, "=0", (60, 0, 0), extra="j1").replace("v=0", "v=0") + 'k i0 t4 p"100 100 300 80 250 300"\n',
    "across-the-seam": image_line(0, 70, (175, 0, 0)),
}


@needs_nona
@pytest.mark.parametrize("name", sorted(MASKS))
def test_masks_and_seams_match_nona(photo, name):
    check(render_both(photo, pano_line() + MASKS[name]))


@needs_nona
def test_panorama_crop_and_whole_canvas_layers_match_nona(photo):
    two = image_line(0, 70, (0, 0, 0)) + image_line(0, 70, (60, 0, 0))
    check(render_both(photo, pano_line(extra="S100,700,50,350") + two))
    pairs = render_both(photo, pano_line(output="TIFF_m c:NONE") + two)
    for n, q in pairs:
        assert read_layer(q)[0].shape[:2] == (400, 800)
    check(pairs)


def three_views(d: Path):
    pto = pano_line(2, 360, 1000, 500) + "".join(image_line(0, 70, (y, 0, 0), dist="") for y in (0, 50, 100))
    (d / "three.pto").write_text(pto)
    return d / "three.pto"


@pytest.mark.skipif(shutil.which("enblend") is None, reason="enblend is not installed")
def test_enblend_takes_the_layers_unchanged(photo):
    project = three_views(photo)
    subprocess.run([CLI, "stitch", str(project), str(photo / "e_"), "--quiet", "--overwrite"], check=True)
    layers = sorted(str(p) for p in photo.glob("e_*.tif"))
    assert len(layers) == 3
    out = photo / "blended.tif"
    subprocess.run(["enblend", "-o", str(out), *layers], check=True, capture_output=True)
    blended = read_layer(out)[0]
    assert blended[..., -1].max() == 1.0
    # The blend is the layers' union.
    spans = [read_layer(p) for p in layers]
    x0, y0 = min(s[1][0] for s in spans), min(s[1][1] for s in spans)
    x1 = max(s[1][0] + s[0].shape[1] for s in spans)
    y1 = max(s[1][1] + s[0].shape[0] for s in spans)
    assert blended.shape[:2] == (y1 - y0, x1 - x0)


def test_python_layers_are_the_files_pixels(photo):
    project = three_views(photo)
    pp.stitch(str(project), str(photo / "py_"), overwrite=True)
    got = pp.stitch_layers(str(project))
    assert got.canvas == (1000, 500)
    assert [layer.image for layer in got.layers] == [0, 1, 2]
    for layer in got.layers:
        pixels, offset, canvas, _ = read_layer(photo / f"py_{layer.image:04d}.tif")
        assert layer.offset == offset and canvas == (1000, 500)
        assert layer.pixels.dtype == np.uint8 and layer.pixels.shape[2] == 4
        np.testing.assert_array_equal(layer.pixels, np.rint(pixels * 255).astype(np.uint8))


def test_views_cut_from_a_real_panorama_put_back_give_it_again(tmp_path):
    """Truth: eight views of the real Jordan Pond panorama through the lens types with a b c d e g t
    (rendered by panoproj at known parameters), written as a project, stitched back and averaged by
    alpha: against the source, beside the same source through a 200-degree dual fisheye and back."""
    src = pp.read(str(JORDAN))[::2, ::2]  # 2048x1024
    pp.write(str(tmp_path / "src.png"), np.ascontiguousarray(src))
    views = [(0, 0, 0, 0, 100), (3, 90, 20, 5, 160), (21, 180, -10, -3, 170), (10, 270, 5, 2, 160),
             (0, 45, 60, 0, 100), (8, 225, -60, 10, 160), (3, 0, 89, 0, 150), (21, 0, -89, 0, 150)]
    lenses = {0: "rectilinear", 3: "equidistant", 8: "orthographic", 10: "stereographic", 21: "equisolid"}
    lines = [pano_line(2, 360, 2048, 1024)]
    dist = dict(a=0.005, b=-0.01, c=0.004, d=6, e=-4, g=2, t=-1.5)
    for k, (f, yaw, pitch, roll, v) in enumerate(views):
        # Each view at the source's resolution at its centre (convert's default size).
        spec = f"panotools:lens={lenses[f]},hfov={v}," + ",".join(f"{key}={val}" for key, val in dist.items())
        view = pp.convert(src, "equirect", spec, yaw=yaw, pitch=pitch, roll=roll, interp="bicubic")
        pp.write(str(tmp_path / f"v{k}.png"), view)
        lines.append(image_line(f, v, (yaw, pitch, roll), " ".join(f"{key}{val}" for key, val in dist.items()),
                                name=f"v{k}.png", size=(view.shape[1], view.shape[0])))
    (tmp_path / "views.pto").write_text("".join(lines))
    layers = pp.stitch_layers(str(tmp_path / "views.pto"), interp="bicubic")
    total, weight = np.zeros((1024, 2048, 3)), np.zeros((1024, 2048))
    for layer in layers.layers:
        x, y = layer.offset
        h, w = layer.pixels.shape[:2]
        a = layer.pixels[..., 3] > 0
        total[y:y + h, x:x + w][a] += layer.pixels[..., :3][a]
        weight[y:y + h, x:x + w][a] += 1
    covered = weight > 0
    assert covered.mean() > 0.98
    mean = total[covered] / weight[covered][:, None]
    stitched = 10 * np.log10(255 ** 2 / np.mean((mean - src[covered].astype(np.float64)) ** 2))
    dual = pp.convert(pp.convert(src, "equirect", "dual-fisheye:fov=200", interp="bicubic"),
                      "dual-fisheye:fov=200", "equirect", size=(2048, 1024), interp="bicubic")
    through_dual = 10 * np.log10(255 ** 2 / np.mean((dual.astype(np.float64) - src) ** 2))
    print(f"views stitched back: {stitched:.2f} dB over {covered.mean():.1%} of the sphere; "
          f"through a dual fisheye: {through_dual:.2f} dB")
    # Two bicubic resamplings of the real photo's detail each way (about 27 dB both; a view turned
    # the wrong way, or a lens parameter misread, is under 15).
    assert stitched > 25
    assert stitched > through_dual - 1.5


@pytest.mark.parametrize("text,kind,what", [
    ("p f2 w400 h200 v360\ni w60 h40 f0 v50 zz1 n\"a.png\"\n", ValueError, r"t.pto:2: i line: unknown token 'zz1'"),
    ("p f2 w400 h200 v360\ni w60 h40 f0 vnan n\"a.png\"\n", ValueError, "token vnan: expected a finite number"),
    ("p f13 w400 h200 v360\ni w60 h40 f0 v50 n\"a.png\"\n", ValueError, "token f13: this panorama projection"),
    ("p f2 w400 h200 v360\ni w60 h40 f5 v50 n\"a.png\"\n", ValueError, "token f5: this lens type is not supported"),
    ("p f2 w400 h200 v360\ni w60 h40 f0 v50 n\"gone.png\"\n", FileNotFoundError, "gone.png"),
    ("p f2 w400 h200 v360\ni w60 h40 f0 v50 n\"a.png\"\nk i0 t0 p\"1 1 2 2\"\n", ValueError,
     "a mask needs at least 3 points"),
    ("p f2 w4000000 h2000000 v360\ni w60 h40 f0 v50 n\"a.png\"\n", MemoryError, "over the memory limit"),
    ("p f2 w400 h200 v360\ni w60 h40 f0 v50 Ra-9 n\"a.png\"\n", ValueError, "t.pto:2: i line: response Ra-9 .* not monotonic"),
    ("p f2 w400 h200 v360\ni w60 h40 f0 v50 Va1 Vb-1.5 Vm5 n\"a.png\"\n", ValueError, "vignetting Va1 Vb-1.5 .* falls to"),
])
def test_bad_projects_raise_naming_the_line(tmp_path, text, kind, what):
    pp.write(str(tmp_path / "a.png"), np.zeros((40, 60, 3), np.uint8))
    (tmp_path / "t.pto").write_text(text)
    with pytest.raises(kind, match=what):
        pp.stitch(str(tmp_path / "t.pto"), str(tmp_path / "l_"), memory_limit="1G")
    assert not list(tmp_path.glob("l_*"))
    r = subprocess.run([CLI, "stitch", str(tmp_path / "t.pto"), str(tmp_path / "l_"), "--memory-limit", "1G"],
                       capture_output=True, text=True)
    assert r.returncode == 1 and len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert not list(tmp_path.glob("l_*"))
