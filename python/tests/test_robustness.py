"""The robustness suite: the command and the Python module at their file boundary, under faults,
hostile files, absurd sizes, bad parameters and signals (the library's own cases are in
tests/robustness_test.cpp). Table-driven; every case asserts

- the exit status (1) or the exception's class,
- one line on stderr naming the value,
- that nothing was written, left behind or clobbered (the folder's listing and old files' bytes),
- bounded memory: the child's peak RSS (os.wait4), under 300 MB for hostile files,
- and a timeout, as a guard against hangs (not a timing assertion).

Write faults are injected below every library: RLIMIT_FSIZE (the kernel fails each write past an
offset with EFBIG), strace's syscall injection (ENOSPC, EDQUOT, EIO on write; EIO on fsync; EROFS
on rename) and, where a mount is permitted, a 1 MiB tmpfs. Each case checks that its fault fired.
Cases marked ``why`` reproduce failures the code once had (data lost or written half), each
fixed at its mechanism.
"""
import importlib.util
import json
import os
import pathlib
import re
import resource
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import threading
import time
import zlib

import numpy as np
import pytest

import panoproj as pp
from conftest import HUGE_HDR, child_env, huge_exr, huge_tiff, native_command, runs_as_nobody, smooth_equirect
from folder_race import folder_race

HOSTILE_RSS = 300 << 20
DEFAULT_RSS = 1500 << 20
STRACE = shutil.which("strace")
# GNU time: the command's own peak memory. A child's ru_maxrss counts the memory of the process it
# was forked (or vforked) from until it execs, here a pytest worker's hundreds of MB.
TIME = shutil.which("time")


# ---------------------------------------------------------------------------------------------
# Running the command

class Run:
    def __init__(self, code, out, err, rss, trace=""):
        self.code, self.out, self.err, self.rss, self.trace = code, out, err, rss, trace

    def error_line(self):
        lines = [l for l in self.err.splitlines() if l.strip()]
        assert len(lines) == 1, f"expected one line on stderr, got {lines!r}"
        return lines[0]


def run(cli, args, cwd, *, fsize=None, strace=None, timeout=60, on_start=None):
    """Runs the command in cwd; fsize: RLIMIT_FSIZE bytes; strace: injection arguments."""
    trace_path = pathlib.Path(cwd) / ".trace"
    cmd = [os.path.abspath(cli)] + [str(a) for a in args]
    if strace:
        cmd = [STRACE, "-f", "-qq", "-o", str(trace_path)] + strace + cmd

    def limits():
        if fsize is not None:
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # ignored dispositions survive exec
            resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, resource.RLIM_INFINITY))

    # (Signals sent by on_start are for the command itself: no time between.)
    measured = TIME is not None and on_start is None
    if measured:
        fd, rss_path = tempfile.mkstemp(prefix="panoproj-rss-")
        os.close(fd)
        cmd = [TIME, "-f", "%M", "-o", rss_path] + cmd
    # Pipes, not files: RLIMIT_FSIZE must not stop the error line itself.
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, cwd=cwd,
                         preexec_fn=limits, start_new_session=measured)
    texts = {}

    def drain(name, pipe):
        texts[name] = pipe.read().decode(errors="replace")

    readers = [threading.Thread(target=drain, args=(n, f)) for n, f in (("out", p.stdout), ("err", p.stderr))]
    for t in readers:
        t.start()
    timer = threading.Timer(timeout, (lambda: os.killpg(p.pid, signal.SIGKILL)) if measured else p.kill)
    timer.start()
    try:
        if on_start:
            on_start(p)
        _, status, usage = os.wait4(p.pid, 0)
    finally:
        timer.cancel()
    for t in readers:
        t.join()
    p.returncode = os.waitstatus_to_exitcode(status)
    rss = usage.ru_maxrss * 1024
    if measured:
        said = _read(pathlib.Path(rss_path)).split("\n")  # ["Command terminated by signal 6", "1234", ""]
        os.unlink(rss_path)
        for line in said:
            if line.startswith("Command terminated by signal "):
                p.returncode = -int(line.rsplit(" ", 1)[1])
            elif line.isdigit():  # (none where RLIMIT_FSIZE stopped time's own file)
                rss = int(line) * 1024
    assert p.returncode != -signal.SIGKILL, f"{args} did not finish within {timeout} s"
    trace = _read(trace_path)
    if trace_path.exists():
        trace_path.unlink()
    return Run(p.returncode, texts["out"], texts["err"], rss, trace)


def _read(path):
    try:
        return pathlib.Path(path).read_text(errors="replace")
    except FileNotFoundError:
        return ""


def listing(folder):
    return sorted(p.name for p in pathlib.Path(folder).iterdir() if p.name not in (".stdout", ".stderr", ".trace"))


def snapshot(folder):
    """Every entry's kind and bytes (links by their target), to show nothing changed."""
    shot = {}
    for p in pathlib.Path(folder).iterdir():
        if p.name in (".stdout", ".stderr", ".trace"):
            continue
        if p.is_symlink():
            shot[p.name] = ("link", os.readlink(p))
        elif p.is_dir():
            shot[p.name] = ("dir",)
        elif p.is_file():
            shot[p.name] = ("file", p.read_bytes())
        else:
            shot[p.name] = ("other",)
    return shot


def expect_refused(r, *needles, rss=DEFAULT_RSS):
    assert r.code == 1, f"exit {r.code}, stderr {r.err!r}"
    line = r.error_line()
    assert line.startswith("panoproj: error: "), line
    for n in needles:
        assert n in line, f"{n!r} not in {line!r}"
    assert r.rss < rss, f"peak memory {r.rss >> 20} MB"
    return line


# ---------------------------------------------------------------------------------------------
# Inputs

@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """Small valid inputs of every format, and hostile ones derived from them."""
    d = tmp_path_factory.mktemp("inputs")
    img = smooth_equirect(256, 128)
    paths = {}
    for ext in ("jpg", "png", "ppm", "tif", "exr", "hdr"):
        a = img if ext in ("jpg", "png", "ppm", "tif") else img.astype(np.float32) / 255
        pp.write(str(d / f"pano.{ext}"), a)
        paths[ext] = d / f"pano.{ext}"
    big = smooth_equirect(2048, 1024)
    pp.write(str(d / "big.png"), big)
    paths["big"] = d / "big.png"
    # A JPEG patched to declare 65500 x 32750 (its SOF0 frame header).
    b = bytearray(paths["jpg"].read_bytes())
    sof = b.find(b"\xff\xc0")
    b[sof + 5:sof + 9] = struct.pack(">HH", 32750, 65500)
    (d / "patched.jpg").write_bytes(bytes(b))
    paths["patched_jpeg"] = d / "patched.jpg"
    (d / "huge.tif").write_bytes(huge_tiff())
    paths["huge_tiff"] = d / "huge.tif"
    # A PNG whose IHDR (CRC correct) declares 1000000 x 1000000, then a little deflate data.
    ihdr = b"IHDR" + struct.pack(">IIBBBBB", 1000000, 1000000, 8, 2, 0, 0, 0)
    idat = b"IDAT" + zlib.compress(b"\0" * 10000)
    png = b"\x89PNG\r\n\x1a\n"
    for chunk in (ihdr, idat, b"IEND"):
        png += struct.pack(">I", len(chunk) - 4) + chunk + struct.pack(">I", zlib.crc32(chunk))
    (d / "huge.png").write_bytes(png)
    paths["huge_png"] = d / "huge.png"
    (d / "huge.exr").write_bytes(huge_exr(paths["exr"].read_bytes()))
    paths["huge_exr"] = d / "huge.exr"
    (d / "huge.hdr").write_bytes(HUGE_HDR)
    paths["huge_hdr"] = d / "huge.hdr"
    (d / "huge.ppm").write_bytes(b"P6\n2147483647 2147483647\n255\n" + b"\x02" * 64)
    paths["huge_ppm"] = d / "huge.ppm"
    for ext in ("jpg", "png", "ppm", "tif", "exr", "hdr"):
        data = paths[ext].read_bytes()
        (d / f"cut.{ext}").write_bytes(data[:len(data) // 2])
        paths[f"cut_{ext}"] = d / f"cut.{ext}"
    (d / "garbage.jpg").write_bytes(b"x" * 3000)
    (d / "empty.png").write_bytes(b"")
    os.mkfifo(d / "fifo.jpg")
    (d / "dir.jpg").mkdir()
    os.symlink("/dev/zero", d / "zero.jpg")
    for k in ("garbage", "empty", "fifo", "dir", "zero"):
        paths[k] = d / {"garbage": "garbage.jpg", "empty": "empty.png", "fifo": "fifo.jpg", "dir": "dir.jpg",
                        "zero": "zero.jpg"}[k]
    paths["devzero"] = pathlib.Path("/dev/zero")
    # Faces (front ... down) for face-set inputs.
    faces = d / "faces"
    faces.mkdir()
    for i, n in enumerate(("front", "right", "back", "left", "up", "down")):
        pp.write(str(faces / f"{n}.png"), np.full((32, 32, 3), 40 * i, np.uint8))
    paths["faces"] = faces / "{face}.png"
    return paths


def gpano_jpeg(folder, field, value, base, stereo_mode=None):
    """The sample JPEG with Photo Sphere XMP in which `field` reads `value` (and, if given,
    GSpherical:StereoMode)."""
    fields = dict(ProjectionType="equirectangular", FullPanoWidthPixels="256", FullPanoHeightPixels="128",
                  CroppedAreaImageWidthPixels="256", CroppedAreaImageHeightPixels="128", CroppedAreaLeftPixels="0",
                  CroppedAreaTopPixels="0", PosePitchDegrees="0")
    fields[field] = value
    xmp = ('<x:xmpmeta xmlns:x="adobe:ns:meta/"><rdf:RDF xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#">'
           '<rdf:Description xmlns:GPano="http://ns.google.com/photos/1.0/panorama/" '
           + " ".join(f'GPano:{k}="{v}"' for k, v in fields.items())
           + ("" if stereo_mode is None else
              f' xmlns:GSpherical="http://ns.google.com/videos/1.0/spherical/" GSpherical:StereoMode="{stereo_mode}"')
           + "/></rdf:RDF></x:xmpmeta>").encode()
    payload = b"http://ns.adobe.com/xap/1.0/\0" + xmp
    data = base.read_bytes()
    seg = b"\xff\xe1" + struct.pack(">H", len(payload) + 2) + payload
    out = pathlib.Path(folder) / f"gpano_{field}_{value}.jpg".replace("/", "_")
    out.write_bytes(data[:2] + seg + data[2:])
    return out


# ---------------------------------------------------------------------------------------------
# 1. Bad parameters: exit 1, one line naming the value, nothing written.

PARAMS = [
    # (id, args after "convert IN OUT" unless they start with a subcommand, needle, why)
    ("pitch_1e308", ["--to", "fisheye", "--pitch", "1e308"], "pitch: 1e+308 (expected degrees within", True),
    ("pitch_nan", ["--to", "fisheye", "--pitch", "nan"], "pitch: nan (expected a finite angle", False),
    ("yaw_inf", ["--to", "fisheye", "--yaw", "inf"], "yaw: inf", False),
    ("roll_text", ["--to", "fisheye", "--roll", "abc"], "--roll", False),
    ("threads_negative", ["--to", "fisheye", "--threads", "-5"], "threads: -5", False),
    ("threads_huge", ["--to", "fisheye", "--threads", "100000"], "threads: 100000", False),
    ("threads_past_int64", ["--to", "fisheye", "--threads", "99999999999999999999"],
     "--threads: 99999999999999999999 is not a 64-bit integer", False),
    ("threads_float", ["--to", "fisheye", "--threads", "1e3"], "--threads: 1e3 is not a 64-bit integer", False),
    ("alpha_with_value", ["--to", "fisheye", "--alpha=maybe"], "--alpha", False),
    ("size_zero", ["--to", "fisheye", "--size", "0x0"], "size: 0x0", False),
    ("size_text", ["--to", "fisheye", "--size", "big"], "size: big", False),
    ("size_2e32", ["--to", "fisheye", "--size", "4294967296x4294967296"], "4294967296x4294967296", True),
    ("size_2e31_by_1", ["--to", "equirect", "--size", "2147483648x1"], "2147483648x1", True),
    ("size_4e6_squared", ["--to", "fisheye", "--size", "4000000x4000000"], "needs 16 TB", True),
    ("jpeg_over_65500", ["--to", "equirect", "--size", "65501x16"], "over the JPEG limit of 65500", False),
    ("memory_limit_text", ["--to", "fisheye", "--memory-limit", "lots"], "memory limit: lots", False),
    ("memory_limit_small", ["--to", "fisheye", "--size", "4000x4000", "--memory-limit", "10M"],
     "over the memory limit of 10 MB", False),
    ("interp", ["--to", "fisheye", "--interp", "cubic"], "cubic", False),
    ("engine", ["--to", "fisheye", "--engine", "gpu"], "gpu", False),
    ("antialias", ["--to", "fisheye", "--antialias", "99"], "99", False),
    ("depth", ["--to", "fisheye", "--depth", "int7"], "int7", False),
    ("quality_0", ["--to", "fisheye", "--quality", "0"], "quality: 0 (expected 1 to 100)", False),
    ("quality_101", ["--to", "fisheye", "--quality", "101"], "quality: 101 (expected 1 to 100)", False),
    ("quality_text", ["--to", "fisheye", "--quality", "high"], "--quality", False),
    ("subsampling", ["--to", "fisheye", "--subsampling", "411"], "subsampling 411 (expected 420, 422 or 444)", False),
    ("decode_scale_3", ["--to", "fisheye", "--decode-scale", "3"], "--decode-scale 3 (expected auto, 1, 2, 4 or 8)",
     False),
    ("decode_scale_png", ["--to", "fisheye", "--decode-scale", "4"], "only JPEG sources decode at a scale", False),
    ("output_extension", ["--to", "fisheye", "--size", "32x32", "OUT=o.bmp"], "no image format for its extension",
     False),
    ("accuracy_decode_scale", ["accuracy", "--to", "fisheye", "--decode-scale", "memory,5"], "--decode-scale: 5", False),
    ("fill", ["--to", "fisheye", "--fill", "purple"], "purple", False),
    ("unknown_projection", ["--to", "mercatorish"], "mercatorish", False),
    ("fov_400", ["--to", "fisheye:fov=400"], "fov", False),
    ("fov_nan", ["--to", "fisheye:fov=nan"], "fov", False),
    # the map and lens forms' keys
    ("mercator_lat_max_90", ["--to", "mercator:lat_max=90"], "lat_max=90 is out of range (expected 0 < lat_max < 90)", False),
    ("tm_x_max_nan", ["--to", "transverse-mercator:x_max=nan"], "x_max=nan is not finite", False),
    ("cea_lat_ts_90", ["--to", "cylindrical-equal-area:lat_ts=90"], "lat_ts=90 is out of range", False),
    ("map_aspect", ["--to", "mollweide:aspect=square"], "aspect=square is not a valid value (expected one of keep|stretch)",
     False),
    ("panini_hfov_wide", ["--to", "panini:d=0,hfov=180"], "hfov=180 is past what the law maps one to one (expected < 180",
     False),
    ("panini_vc_2", ["--to", "panini:vc=2"], "vc=2 is out of range (expected 0 <= vc <= 1)", False),
    ("panini_keys_of_the_other_model", ["--to", "panini:model=opencv,d=2"], "d and vc apply to model=sharpless", False),
    ("compressed_a_0", ["--to", "compressed-rectilinear:a=0"], "a=0 is out of range", False),
    ("thoby_past_turn", ["--to", "fisheye:model=thoby,fov=260"], "fov=260 is past where model=thoby with k2=0.713 turns back",
     False),
    ("k2_without_thoby", ["--to", "fisheye:k2=0.5"], "k2 applies to model=thoby", False),
    # the calibrated camera models: wrong counts, non-finite values, folding calibrations, fields
    # past the law's domain
    ("brown_radial_fold", ["--to", "brown-conrady:fov=120,k1=-0.3"], "fold the lens law back at theta=46.5", False),
    ("brown_k4_nan", ["--to", "brown-conrady:k4=nan"], "k4=nan is not finite", False),
    ("brown_prism_folds", ["--to", "brown-conrady:fov=120,s1=2"], "thin-prism terms fold the image", False),
    ("brown_fov_180", ["--to", "brown-conrady:fov=180"], "fov=180 is past the model's domain (expected fov < 180)", False),
    ("omni_xi_negative", ["--to", "omni-radtan:xi=-1"], "xi=-1 is out of range", False),
    ("omni_past_domain", ["--to", "omni-radtan:xi=2,fov=300"], "fov=300 is past the model's domain (expected fov <= 240",
     False),
    ("radtan_fisheye_folds", ["--to", "rad-tan-thin-prism-fisheye:fov=200,k0=-0.0255,k1=0.0998,k2=-0.0697,k3=0.0132,"
                              "k4=0.0034,k5=-0.0012"], "k0..k5 fold the lens law back at theta=96.9", False),
    ("thin_prism_fisheye_inf", ["--to", "thin-prism-fisheye:sx1=inf"], "sx1=inf is not finite", False),
    ("fov_omega_pi", ["--to", "devernay-faugeras:omega=3.2"], "omega=3.2 is out of range (expected 0 < omega < 3.14",
     False),
    ("division_past_fold", ["--to", "division:k=0.3,fov=120"], "fov=120 is past the model's domain (expected fov <= 84.",
     False),
    ("ftheta_no_poly", ["--to", "f-theta"], "f-theta: poly= (expected 2 to 6 coefficients", False),
    ("ftheta_c0", ["--to", "f-theta:poly=1/500"], "poly's c0 = 1.000000 (expected 0", False),
    ("ftheta_decreasing", ["--to", "f-theta:poly=0/-500"], "expected c1 > 0", False),
    ("ftheta_seven", ["--to", "f-theta:poly=0/1/2/3/4/5/6"], "has 7 numbers (expected 2 to 6", False),
    ("ftheta_fold", ["--to", "f-theta:fov=200,poly=0/500/0/-100"], "poly fold the lens law back at theta=73.", False),
    ("ftheta_singular", ["--to", "f-theta:poly=0/500,c=0.5,d=1,e=0.5"], "c, d, e make the affine term singular", False),
    ("ocam_no_centre", ["--to", "ocamcalib:pol=-244/0/0.0017"], "xc and yc are required", False),
    ("ocam_a0_positive", ["--to", "ocamcalib:xc=100,yc=100,pol=244/0/0.0017"], "pol's a0 = 244.000000 (expected a negative",
     False),
    ("ocam_pol_nan", ["--to", "ocamcalib:xc=100,yc=100,pol=-244/nan"], "pol=-244/nan (expected 2 to 16", False),
    ("ocam_other_size", ["--to", "ocamcalib:xc=100,yc=100,pol=-244/0/0.0017,width=640,height=480", "--size", "320x240"],
     "the calibration is of 640x480 images, this frame is 320x240", False),
    ("ocam_from_other_size", ["--from", "ocamcalib:xc=100,yc=100,pol=-244/0/0.0017,width=640,height=480", "--to",
                              "equirect", "--size", "64x32"], "the calibration is of 640x480 images, this frame is", False),
    ("ocam_fov_unreached", ["--to", "ocamcalib:xc=100,yc=100,pol=-244/0/0.0017,fov=350"],
     "pol reaches only fov=23", False),
    ("k2_huge", ["--to", "fisheye:model=thoby,k2=1e300"], "k2=1e300 is out of range (expected 0 < k2 <= 10)", False),
    # cube formats and stereo frames
    ("cube_order_letters", ["--to", "cubemap:order=frbluu"], "order=frbluu is not six distinct letters of f r b l u d", False),
    ("cube_rot_digit", ["--to", "cubemap:rot=00004"], "rot=00004 is not six digits 0-3", False),
    ("cube_pad_and_pad_px", ["--to", "cubemap:pad=0.1,pad_px=2"], "pad and pad_px both given", False),
    ("cube_pad_half", ["--to", "cubemap:pad=0.5"], "pad=0.5 is out of range (expected 0 <= pad <= 0.4)", False),
    ("cube_pad_px_wide", ["--to", "cubemap:face=10,pad_px=5"], "pad_px=5 is over 0.4 of a 10-px cell (expected at most 4)",
     False),
    ("cube_order_long", ["--to", "cubemap:order=" + "f" * 100], "is not six distinct letters", False),
    ("cube_order_huge", ["--to", "cubemap:order=" + "f" * 2000], "order= is 2000 characters long (expected up to 1024)", False),
    ("border_without_eac", ["--to", "cubemap:border=ffmpeg"], "border=ffmpeg needs layout=eac", False),
    ("border_cells_small", ["--to", "cubemap:layout=eac,border=ffmpeg,face=4"], "border=ffmpeg needs cells of at least 5 px",
     False),
    ("preset_with_order", ["--to", "cubemap:preset=threejs,order=frblud"], "preset=threejs sets the order and turns (drop order and rot)",
     False),
    ("preset_on_eac", ["--to", "cubemap:layout=eac,preset=unity"], "preset=unity sets the order and turns (drop layout=eac)",
     False),
    ("preset_value", ["--to", "cubemap:preset=babylon"], "preset=babylon is not a valid value (expected one of none|threejs|unity)",
     False),
    ("axis_without_files", ["--to", "cubemap", "OUT={axis}.png"], "has {face}/{index}/{axis} but --to is not cubemap:layout=files",
     False),
    ("stereo_value", ["--to", "equirect:stereo=lr"], "stereo=lr is not a valid value (expected one of mono|tb|sbs)", False),
    ("stereo_odd_size", ["--to", "equirect:stereo=tb", "--size", "64x33"], "64x33 does not split into two eyes top and bottom",
     False),
    ("eye_on_mono", ["--from", "equirect:eye=right", "--to", "fisheye"], "eye=right picks an eye of a stereo source", False),
    ("eye_on_target", ["--to", "fisheye:eye=left"], "eye= is for the source", False),
    ("stereo_face_files", ["--to", "cubemap:layout=files,stereo=tb", "OUT={face}.png"], "stereo= with layout=files", False),
    ("maps_stereo", ["maps", "m.exr", "--from", "equirect:stereo=tb", "--source-size", "64x64", "--to", "fisheye"],
     "maps: stereo=", False),
    # Photometric keys (a source's response, exposure, white balance, vignetting).
    ("photometry_wb_text", ["--from", "equirect:wb=1/x", "--to", "fisheye"], "wb=1/x (expected two multipliers R/B)",
     False),
    ("photometry_wb_zero", ["--from", "equirect:wb=0/1", "--to", "fisheye"], "white balance Er0: expected a positive",
     False),
    ("photometry_wb_one_number", ["--from", "equirect:wb=1.2", "--to", "fisheye"], "wb=1.2 has 1 numbers", False),
    ("photometry_response_count", ["--from", "equirect:response=0.1/0.2", "--to", "fisheye"],
     "response=0.1/0.2 has 2 numbers (expected emor, linear or five EMoR", False),
    ("photometry_response_word", ["--from", "equirect:response=srgb", "--to", "fisheye"],
     "response=srgb (expected emor, linear or five EMoR", False),
    ("photometry_response_not_monotonic", ["--from", "equirect:response=9/0/0/0/0", "--to", "fisheye"],
     "not monotonic", False),
    ("photometry_response_inf", ["--from", "equirect:response=1e999/0/0/0/0", "--to", "fisheye"],
     "response=1e999/0/0/0/0 (expected", False),
    ("photometry_vignetting_zero", ["--from", "equirect:vignetting=1/-1.2", "--to", "fisheye"],
     "inside the image: nothing can be divided by it", False),
    ("photometry_vignetting_nan", ["--from", "equirect:vignetting=1/nan", "--to", "fisheye"],
     "vignetting=1/nan (expected 1 to 4 coefficients", False),
    ("photometry_vignetting_five", ["--from", "equirect:vignetting=1/0/0/0/0", "--to", "fisheye"],
     "vignetting=1/0/0/0/0 has 5 numbers", False),
    ("photometry_centre_far", ["--from", "equirect:vignetting_centre=1e9/0,vignetting=1/-0.1", "--to", "fisheye"],
     "vignetting centre shift 1e+09,0", False),
    ("photometry_ev_nan", ["--from", "equirect:ev=nan", "--to", "fisheye"], "ev=nan is not finite", False),
    ("photometry_ev_range", ["--from", "equirect:ev=200", "--to", "fisheye"], "ev=200 is out of range", False),
    ("photometry_ev_spread", ["--from", "equirect:ev=-60", "--to", "fisheye:ev=60"], "expected finite EVs at most 64",
     False),
    ("photometry_flat_field_key", ["--from", "equirect:flat_field=f.png", "--to", "fisheye"], "unknown key 'flat_field'",
     False),
    ("photometry_on_target", ["--to", "fisheye:vignetting=1/-0.1"], "vignetting= describes a source's lens", False),
    ("photometry_lens2_on_one_lens", ["--from", "equirect:ev2=1", "--to", "fisheye"], "unknown key 'ev2'", False),
    ("photometry_maps", ["maps", "m.exr", "--from", "fisheye:ev=1", "--source-size", "64x64", "--to", "equirect"],
     "maps: photometric keys", False),
    ("photometry_accuracy", ["accuracy", "--from", "fisheye:vignetting=1/-0.2", "--to", "equirect"],
     "accuracy: photometric keys", False),
    ("unknown_option", ["--to", "fisheye", "--frobnicate"], "--frobnicate", True),
    ("missing_to", [], "--to", True),
    ("faces_without_files_layout", ["--to", "equirect"], "{face}", False),
    ("accuracy_threads", ["accuracy", "--to", "fisheye", "--threads", "-5"], "threads: -5", True),
    ("accuracy_runs", ["accuracy", "--to", "fisheye", "--runs", "0"], "runs: 0", False),
    ("accuracy_size", ["accuracy", "--to", "fisheye", "--size", "4294967296x4294967296"], "4294967296x4294967296", True),
    ("accuracy_from_size", ["accuracy", "--to", "fisheye", "--from-size", "4000000x2000000"], "give --size", False),
    ("accuracy_csv_folder", ["accuracy", "--to", "fisheye", "--csv", "nowhere/a.csv"], "output folder nowhere", True),
    # One job's outputs against each other, before the sweep (it wrote the CSV, then failed on it).
    ("accuracy_same_output", ["accuracy", "--to", "fisheye", "--csv", "r.txt", "--json", "./r.txt"],
     "--csv and --json both name ./r.txt (give each output its own file)", True),
    # Degenerate default sizes (were 256x1, 1x1 ...): refused, naming the spec.
    ("default_size_under_8", ["--to", "equirect:vfov=0.01"], "equirect:vfov=0.01 at the source's resolution would be "
     "256x1 (under 8 px a side: its field spans fewer than 8 of the source's pixels); give --size WxH, or vfov >= ", True),
    ("default_size_1x1", ["--to", "pinhole:hfov=0.01"], "would be 1x1 (under 8 px a side", True),
    # A source or target whose valid region is empty or under a pixel across (was: an empty image).
    ("source_circle_under_a_pixel", ["--from", "fisheye:fov=180,radius=0.6", "--to", "equirect"],
     "from: fisheye:fov=180,radius=0.6 on a 256x128 frame has no pixel that sees a direction", True),
    ("source_circle_off_the_frame", ["--from", "fisheye:fov=180,cx=-200", "--to", "equirect"],
     "(its valid region is empty or under a pixel across)", True),
    ("target_circle_off_the_frame", ["--to", "fisheye:fov=180,cx=5000", "--size", "64x64"],
     "to: fisheye:fov=180,cx=5000 on a 64x64 frame has no pixel that sees a direction", True),
    ("maps_size", ["maps", "m.exr", "--from", "equirect", "--source-size", "64x32", "--to", "fisheye",
                   "--size", "4294967296x4294967296"], "4294967296x4294967296", True),
    ("maps_convention", ["maps", "m.exr", "--from", "equirect", "--source-size", "64x32", "--to", "fisheye",
                         "--convention", "matlab"], "matlab", False),
    ("maps_extension", ["maps", "m.png", "--from", "equirect", "--source-size", "64x32", "--to", "fisheye"],
     "cannot hold float maps", False),
    ("no_subcommand", ["--version-of-nothing"], "panoproj: error:", True),
    # GoPro MAX strips (two images of one frame, or both stacked): sizes no preset holds, bands and
    # feathers out of range.
    ("gopro_max_no_preset", ["--from", "gopro-max", "--to", "equirect"], "strips of 256x64 match no preset (max-5.6k", False),
    ("gopro_max_band", ["--from", "gopro-max:face=64,outer=96,band=97", "--to", "equirect"], "an even band narrower", False),
    ("gopro_max_feather", ["--from", "gopro-max:face=64,outer=96,band=8,feather=60", "--to", "equirect"],
     "is wider than the band", False),
    ("gopro_max_feather_nan", ["--from", "gopro-max:face=64,outer=96,band=8,feather=nan", "--to", "equirect"], "feather",
     False),
    ("gopro_max_three_inputs", ["OUT=o.png", "--from", "gopro-max", "--to", "equirect", "EXTRA"], "for --from", False),
]


def _table(rows):
    """Rows as pytest params named by their first field, marked `why` where their last says so."""
    return [pytest.param(r, id=r[0], marks=[pytest.mark.why] if r[-1] is True else []) for r in rows]


@pytest.mark.parametrize("case", _table(PARAMS))
def test_bad_parameters(cli, files, tmp_path, case):
    name, args, needle, _ = case
    if args and args[0] in ("accuracy", "maps") or name == "no_subcommand":
        full = args
    else:
        out = "o.jpg" if name == "jpeg_over_65500" else ("{face}.png" if name == "faces_without_files_layout" else "o.png")
        out = next((a[4:] for a in args if a.startswith("OUT=")), out)
        extra = [files["png"]] * 2 if "EXTRA" in args else []  # (three inputs)
        full = ["convert", files["png"], *extra, out] + [a for a in args if not a.startswith("OUT=") and a != "EXTRA"]
    before = snapshot(tmp_path)
    r = run(cli, full, tmp_path)
    expect_refused(r, needle)
    assert r.out == "", r.out  # refused before any work (an accuracy sweep prints its table)
    assert snapshot(tmp_path) == before


# Spec files (@file): each refused in one line naming the file.
def spec_file_cases(tmp):
    (tmp / "dup.json").write_text('{"projection": "fisheye", "projection": "pinhole"}')
    (tmp / "dupkey.yaml").write_text("projection: fisheye\nfov: 180\nfov: 200\n")
    (tmp / "nested.json").write_text('{"projection": "fisheye", "fov": {"a": 1}}')
    (tmp / "specdir").mkdir()
    os.mkfifo(tmp / "spec.fifo")
    ocam = "#polynomial coefficients for the DIRECT mapping function\n"
    (tmp / "ocam_short.txt").write_text(ocam + "5 -244.5 0 0.0017\n")
    (tmp / "ocam_count.txt").write_text(ocam + "5 -244.5 0 0.0017\n3 1 2 3\n383 511\n1 0 0\n768 1024\n")
    (tmp / "ocam_nan.txt").write_text(ocam + "3 -244.5 nan 0.0017\n3 1 2 3\n383 511\n1 0 0\n768 1024\n")
    (tmp / "ocam_centre.txt").write_text(ocam + "3 -244.5 0 0.0017\n3 1 2 3\n383\n1 0 0\n768 1024\n")
    (tmp / "ocam_size.txt").write_text(ocam + "3 -244.5 0 0.0017\n3 1 2 3\n383 511\n1 0 0\n768\n")
    chain = "cam0:\n  camera_model: {}\n  distortion_coeffs: {}\n  distortion_model: {}\n  intrinsics: {}\n"
    (tmp / "kalibr_model.yaml").write_text(chain.format("mei", "[]", "none", "[1, 2, 3, 4]"))
    (tmp / "kalibr_combo.yaml").write_text(chain.format("ds", "[0.1]", "radtan", "[0.1, 0.5, 300, 300, 320, 240]"))
    (tmp / "kalibr_count.yaml").write_text(chain.format("omni", "[0.1, 0.2]", "radtan", "[1.8, 700, 700, 640]"))
    (tmp / "kalibr_list.yaml").write_text(chain.format("pinhole", "0.1", "radtan", "[700, 700, 640, 512]"))
    (tmp / "kalibr_inf.yaml").write_text(chain.format("pinhole", "[]", "none", "[700, inf, 640, 512]"))
    (tmp / "kalibr_two.yaml").write_text(chain.format("pinhole", "[]", "none", "[700, 700, 640, 512]") +
                                         chain.format("pinhole", "[]", "none", "[700, 700, 640, 512]").replace("cam0", "cam1"))
    for name, body in {"model": "1 PINHOLEISH 640 480 500 500 320 240\n", "count": "1 PINHOLE 640 480 500 500 320\n",
                       "nan": "1 PINHOLE 640 480 500 nan 320 240\n", "zero": "1 PINHOLE 0 480 500 500 320 240\n",
                       "fields": "1 PINHOLE 640\n", "twice": "1 SIMPLE_PINHOLE 64 48 50 32 24\n" * 2}.items():
        (tmp / f"colmap_{name}").mkdir()
        (tmp / f"colmap_{name}" / "cameras.txt").write_text(body)
    camera = struct.pack("<IiQQ", 1, 1, 640, 480) + struct.pack("<4d", 500, 500, 320, 240)
    for name, body in {"short": struct.pack("<Q", 1) + camera[:-5], "absurd": struct.pack("<Q", 10**15) + camera,
                       "model_id": struct.pack("<Q", 1) + struct.pack("<IiQQ", 1, 42, 640, 480) + camera[24:],
                       "trailing": struct.pack("<Q", 1) + camera + b"xx"}.items():
        (tmp / f"colmapbin_{name}").mkdir()
        (tmp / f"colmapbin_{name}" / "cameras.bin").write_bytes(body)
    return [("dup_projection", "@dup.json", 'the key "projection" is given twice'),
            ("colmap_model", "@colmap_model/cameras.txt", "camera 1 has the model PINHOLEISH (expected one of COLMAP's"),
            ("colmap_count", "@colmap_count/cameras.txt", "camera 1 (PINHOLE) has 3 parameters (expected 4)"),
            ("colmap_nan", "@colmap_nan/cameras.txt", "camera 1 has a parameter nan (expected finite numbers)"),
            ("colmap_zero", "@colmap_zero/cameras.txt", "camera 1 is 0x480 pixels"),
            ("colmap_fields", "@colmap_fields/cameras.txt", "line 1 has 3 fields (expected CAMERA_ID MODEL WIDTH HEIGHT"),
            ("colmap_twice", "@colmap_twice/cameras.txt#1", "camera 1 is listed twice"),
            ("colmapbin_short", "@colmapbin_short/cameras.bin", "cut short in the parameters at byte 56"),
            ("colmapbin_absurd", "@colmapbin_absurd/cameras.bin", "says it holds 1000000000000000 cameras"),
            ("colmapbin_model_id", "@colmapbin_model_id/cameras.bin", "camera 1 has the model id 42 (expected 0 to 17)"),
            ("colmapbin_trailing", "@colmapbin_trailing/cameras.bin", "2 bytes after its cameras"),
            ("ocam_short", "@ocam_short.txt", "ocam_short.txt: 1 data lines (expected OCamCalib's calib_results.txt"),
            ("ocam_count", "@ocam_count.txt", "the pol line gives 5 then 3 coefficients"),
            ("ocam_nan", "@ocam_nan.txt", "pol holds 'nan' (expected a finite number)"),
            ("ocam_centre", "@ocam_centre.txt", "the centre line has 1 values"),
            ("ocam_size", "@ocam_size.txt", "the image size line has 1 values"),
            ("kalibr_model", "@kalibr_model.yaml", "camera_model mei (expected pinhole, omni, ds or eucm)"),
            ("kalibr_combo", "@kalibr_combo.yaml", "camera_model ds with distortion_model radtan"),
            ("kalibr_count", "@kalibr_count.yaml", "cam0's intrinsics (omni) has 4 values (expected 5)"),
            ("kalibr_list", "@kalibr_list.yaml", "cam0's distortion_coeffs is not a [..] list"),
            ("kalibr_inf", "@kalibr_inf.yaml", "cam0's intrinsics holds 'inf' (expected a finite number)"),
            ("kalibr_two", "@kalibr_two.yaml", "holds cameras cam0, cam1 (name one"),
            ("kalibr_no_camera", "@kalibr_two.yaml#cam5", "no camera cam5 (it holds cam0, cam1)"),
            ("fragment_not_kalibr", "@dupkey.yaml#cam0", "#cam0 names a camera, but"),
            ("dup_key", "@dupkey.yaml", 'the key "fov" is given twice'),
            ("nested", "@nested.json", "not a string or number"),
            ("directory", "@specdir", "cannot read the spec file specdir: a directory"),
            ("fifo", "@spec.fifo", "cannot read the spec file spec.fifo: a FIFO"),
            ("missing", "@none.yaml", "the spec file none.yaml does not exist")]


SPEC_IDS = ["dup_projection", "dup_key", "nested", "directory", "fifo", "missing", "ocam_short", "ocam_count", "ocam_nan",
            "ocam_centre", "ocam_size", "kalibr_model", "kalibr_combo", "kalibr_count", "kalibr_list", "kalibr_inf", "kalibr_two",
            "kalibr_no_camera", "fragment_not_kalibr", "colmap_model", "colmap_count", "colmap_nan", "colmap_zero",
            "colmap_fields", "colmap_twice", "colmapbin_short", "colmapbin_absurd", "colmapbin_model_id", "colmapbin_trailing"]


@pytest.mark.parametrize("which", [pytest.param(i, marks=[pytest.mark.why] if i in ("dup_projection", "directory", "fifo")
                                                else []) for i in SPEC_IDS])
def test_bad_spec_files(cli, files, tmp_path, which):
    cases = {c[0]: c for c in spec_file_cases(tmp_path)}
    _, spec, needle = cases[which]
    before = snapshot(tmp_path)
    r = run(cli, ["convert", files["png"], "o.png", "--to", spec], tmp_path, timeout=20)
    expect_refused(r, needle)
    assert snapshot(tmp_path) == before


@pytest.mark.parametrize("mode,needle", [("sideways", 'GSpherical:StereoMode is "sideways"'),
                                         ("top-bottom\x01", "GSpherical:StereoMode is"),
                                         ("top-bottom", "an eye is 256x64 but its cropped area is 256x128")])
@pytest.mark.why
def test_stereo_modes_that_do_not_fit_are_refused(cli, files, tmp_path, mode, needle):
    """An unknown GSpherical:StereoMode, or top-bottom on a frame whose GPano fields describe the
    whole frame rather than one eye, is refused by name with --from as the way round it."""
    src = gpano_jpeg(tmp_path, "FullPanoHeightPixels", "128", files["jpg"], mode)
    before = snapshot(tmp_path)
    r = run(cli, ["convert", src, "o.png", "--to", "pinhole", "--size", "32x32"], tmp_path)
    expect_refused(r, needle, "--from")
    assert snapshot(tmp_path) == before


@pytest.mark.why
def test_yaml_spec_with_a_byte_order_mark_is_read(cli, files, tmp_path):
    (tmp_path / "bom.yaml").write_bytes(b"\xef\xbb\xbfprojection: fisheye\nfov: 180\n")
    r = run(cli, ["convert", files["png"], "o.png", "--to", "@bom.yaml", "--size", "32x32", "-q"], tmp_path)
    assert r.code == 0, r.err
    assert (tmp_path / "o.png").exists()


@pytest.mark.parametrize("field,value", [("FullPanoWidthPixels", "nan"), ("FullPanoWidthPixels", "inf"),
                                         ("CroppedAreaLeftPixels", "-inf"), ("CroppedAreaTopPixels", "abc"),
                                         ("PosePitchDegrees", "nan"), ("FullPanoHeightPixels", "1e400")])
@pytest.mark.why
def test_gpano_fields_that_are_not_finite_numbers_are_refused(cli, files, tmp_path, field, value):
    src = gpano_jpeg(tmp_path, field, value, files["jpg"])
    before = snapshot(tmp_path)
    r = run(cli, ["convert", src, "o.png", "--to", "pinhole", "--size", "32x32"], tmp_path)
    expect_refused(r, f"GPano:{field} is \"{value}\"", "--from")
    assert snapshot(tmp_path) == before


# ---------------------------------------------------------------------------------------------
# 2. Hostile and odd inputs: refused in one line, within 300 MB, without hanging.

HOSTILE = [
    ("patched_jpeg", "too few to hold them", True), ("huge_tiff", "too few to hold them", True),
    ("huge_png", "too few to hold them", False), ("huge_exr", "cannot read", False),
    ("huge_hdr", "too few to hold them", False), ("huge_ppm", "too few to hold them", False),
    ("cut_jpg", "cannot read", False), ("cut_png", "cannot read", False), ("cut_ppm", "cannot read", False),
    ("cut_tif", "cannot read", False), ("cut_exr", "cannot read", False), ("cut_hdr", "cannot read", False),
    ("garbage", "not a JPEG, PNG, PPM/PGM, TIFF, OpenEXR or Radiance HDR image", False), ("empty", "the file is empty", False),
    ("fifo", "a FIFO", True), ("dir", "a directory", False), ("zero", "a device", True), ("devzero", "a device", True),
]


@pytest.mark.parametrize("case", _table(HOSTILE))
def test_hostile_inputs(cli, files, tmp_path, case):
    key, needle, _ = case
    src = files[key]
    before = snapshot(tmp_path)
    r = run(cli, ["convert", src, "o.png", "--to", "fisheye", "--size", "64x64", "--from", "equirect"], tmp_path,
            timeout=30)
    line = expect_refused(r, needle, rss=HOSTILE_RSS)
    assert str(src) in line
    assert len(line) < 400
    assert snapshot(tmp_path) == before


def test_a_region_of_a_plausible_file_still_converts(cli, files, tmp_path):
    # The patched JPEG's first rows are plausible for its bytes: a view of them decodes what is
    # there and fails cleanly at the damage, within bounded memory.
    r = run(cli, ["convert", files["patched_jpeg"], "o.png", "--from", "equirect", "--to", "pinhole:hfov=1",
                  "--pitch", "89", "--size", "16x16"], tmp_path, timeout=60)
    assert r.rss < HOSTILE_RSS
    assert r.code in (0, 1)
    if r.code:
        r.error_line()
        assert listing(tmp_path) == []


# ---------------------------------------------------------------------------------------------
# 3. Outputs: never clobbered without --overwrite, never through links, nothing half-written.

def test_existing_output_needs_overwrite(cli, files, tmp_path):
    (tmp_path / "o.png").write_bytes(b"old")
    r = run(cli, ["convert", files["png"], "o.png", "--to", "fisheye", "--size", "32x32"], tmp_path)
    expect_refused(r, "output o.png exists (pass --overwrite to replace it)")
    assert (tmp_path / "o.png").read_bytes() == b"old"


@pytest.mark.why
def test_dangling_link_output_needs_overwrite(cli, files, tmp_path):
    os.symlink(tmp_path / "nowhere.png", tmp_path / "o.png")
    r = run(cli, ["convert", files["png"], "o.png", "--to", "fisheye", "--size", "32x32"], tmp_path)
    expect_refused(r, "output o.png exists (a link)")
    assert os.path.islink(tmp_path / "o.png") and not (tmp_path / "nowhere.png").exists()


def test_overwriting_a_link_replaces_the_link_not_its_target(cli, files, tmp_path):
    (tmp_path / "precious").write_bytes(b"precious")
    os.symlink(tmp_path / "precious", tmp_path / "o.png")
    r = run(cli, ["convert", files["png"], "o.png", "--to", "fisheye", "--size", "32x32", "--overwrite", "-q"], tmp_path)
    assert r.code == 0, r.err
    assert not os.path.islink(tmp_path / "o.png")
    assert (tmp_path / "precious").read_bytes() == b"precious"


@pytest.mark.parametrize("case", ["directory", "missing_folder", "same_path", "hard_link", "symlink_to_input"])
def test_outputs_that_cannot_be_written(cli, files, tmp_path, case):
    src = tmp_path / "in.png"
    shutil.copy(files["png"], src)
    out, needle = "o.png", ""
    if case == "directory":
        (tmp_path / "o.png").mkdir()
        needle = "output o.png is a directory"
    elif case == "missing_folder":
        out, needle = "nowhere/o.png", "output folder nowhere does not exist"
    elif case == "same_path":
        out, needle = "in.png", "is the input"
    elif case == "hard_link":
        os.link(src, tmp_path / "o.png")
        needle = "is the input"
    else:
        os.symlink(src, tmp_path / "o.png")
        needle = "is the input"
    before = snapshot(tmp_path)
    r = run(cli, ["convert", "in.png", out, "--to", "equirect", "--size", "32x16", "--overwrite"], tmp_path)
    expect_refused(r, needle)
    assert snapshot(tmp_path) == before


@pytest.mark.why
def test_long_output_names_fit_their_temporaries(cli, files, tmp_path):
    name = "n" * 245 + ".png"  # 249 bytes: a temporary named after it would pass NAME_MAX
    r = run(cli, ["convert", files["png"], name, "--to", "fisheye", "--size", "32x32", "-q"], tmp_path)
    assert r.code == 0, r.err
    assert listing(tmp_path) == [name]


@pytest.mark.why
def test_face_set_with_a_directory_among_its_faces_replaces_none(cli, files, tmp_path):
    for n in ("front", "right", "back", "up", "down"):
        (tmp_path / f"{n}.png").write_bytes(b"old " + n.encode())
    (tmp_path / "left.png").mkdir()
    before = snapshot(tmp_path)
    r = run(cli, ["convert", files["png"], "{face}.png", "--to", "cubemap:layout=files", "--size", "16x16",
                  "--overwrite"], tmp_path)
    expect_refused(r, "left.png is a directory")
    assert "Success" not in r.err
    assert snapshot(tmp_path) == before


@pytest.mark.skipif(not STRACE, reason="strace (a test oracle) is not installed")
@pytest.mark.why
def test_temporaries_are_created_exclusively_under_unpredictable_names(cli, files, tmp_path):
    names = []
    for k in range(2):
        r = run(cli, ["convert", files["png"], f"o{k}.png", "--to", "fisheye", "--size", "32x32", "-q"], tmp_path,
                strace=["-e", "trace=openat"])
        assert r.code == 0, r.err
        opens = [l for l in r.trace.splitlines() if ".panoproj-" in l and "O_CREAT" in l]
        assert len(opens) == 1, opens
        assert "O_EXCL" in opens[0] and "O_NOFOLLOW" in opens[0], opens[0]
        # .panoproj-<pid space>-<pid>-<start time>-<16 hex>.tmp: the process (for stale ones) and a
        # random part.
        names.append(re.search(r"\.panoproj-[0-9a-f]{8}-[0-9]+-[0-9]+-([0-9a-f]{16})\.tmp", opens[0]).group(1))
    assert names[0] != names[1]


@pytest.mark.why
def test_planted_links_at_temporary_names_are_never_followed(cli, files, tmp_path):
    # Without knowing the random name, an attacker can only plant many: none is followed (the
    # temporary is created with O_EXCL | O_NOFOLLOW, so a planted name would be skipped).
    # The temporary names an earlier panoproj used (.o.panoproj-tmp-PID.png), for the next 300 PIDs.
    (tmp_path / "root-only").write_bytes(b"secret")
    last = int(pathlib.Path("/proc/sys/kernel/ns_last_pid").read_text())
    for k in range(1, 301):
        os.symlink(tmp_path / "root-only", tmp_path / f".o.panoproj-tmp-{last + k}.png")
    r = run(cli, ["convert", files["png"], "o.png", "--to", "fisheye", "--size", "32x32", "-q"], tmp_path)
    assert r.code == 0, r.err
    assert (tmp_path / "root-only").read_bytes() == b"secret"
    assert not os.path.islink(tmp_path / "o.png")


# ---------------------------------------------------------------------------------------------
# 4. Write faults: the write fails, the old file is intact, no temporary is left, one line names
#    the output and the system's reason; the fault is shown to have fired.

FORMATS = ["jpg", "png", "tif", "exr", "hdr"]


def _fault_target(kind, ext):
    """(args, outputs) of a job writing `kind` in format ext."""
    if kind == "convert":
        return ["--to", "fisheye", "--size", "192x192", "--overwrite"], [f"o.{ext}"]
    if kind == "faces":
        return ["--to", "cubemap:layout=files", "--size", "64x64", "--overwrite"], \
            [f"{n}.{ext}" for n in ("front", "right", "back", "left", "up", "down")]
    raise AssertionError(kind)


def _old_files(tmp_path, outputs):
    for o in outputs:
        (tmp_path / o).write_bytes(b"old " + o.encode())


def _assert_old_intact(tmp_path, outputs):
    for o in outputs:
        assert (tmp_path / o).read_bytes() == b"old " + o.encode(), o
    assert sorted(listing(tmp_path)) == sorted(outputs), listing(tmp_path)


FSIZE_CASES = [(kind, ext, cut) for kind in ("convert",) for ext in FORMATS for cut in (0, 0.3, 0.97)] + \
              [("faces", "png", cut) for cut in (0, 0.5, 0.97)] + [("faces", "jpg", 0.5)]


@pytest.mark.parametrize("kind,ext,cut", FSIZE_CASES, ids=[f"{k}-{e}-{c}" for k, e, c in FSIZE_CASES])
@pytest.mark.why
def test_writes_cut_at_a_byte_offset(cli, files, tmp_path, kind, ext, cut):
    args, outputs = _fault_target(kind, ext)
    full = ["convert", files["png"], outputs[0] if kind == "convert" else "{face}." + ext] + args
    r = run(cli, full + ["-q"], tmp_path)
    assert r.code == 0, r.err
    size = max((tmp_path / o).stat().st_size for o in outputs)
    limit = int(size * cut)
    _old_files(tmp_path, outputs)
    r = run(cli, full, tmp_path, fsize=limit)
    line = expect_refused(r, "cannot write ", f"writing byte {limit} of", "File too large")
    assert ".panoproj-" not in line
    _assert_old_intact(tmp_path, outputs)


@pytest.mark.parametrize("what", ["maps", "csv", "json", "plot"])
@pytest.mark.why
def test_other_outputs_cut_at_a_byte_offset(cli, tmp_path, what):
    if what == "maps":
        args, out = ["maps", "m.exr", "--from", "equirect", "--source-size", "256x128", "--to", "fisheye",
                     "--size", "64x64", "--overwrite"], "m.exr"
    else:
        out = {"csv": "a.csv", "json": "a.json", "plot": "a.png"}[what]
        args = ["accuracy", "--to", "fisheye", "--from-size", "128x64", "--size", "32x32", "--interp", "bilinear",
                "--antialias", "off", "--engine", "simd", "--runs", "1", f"--{what}", out, "--overwrite"]
    (tmp_path / out).write_bytes(b"old " + out.encode())
    r = run(cli, args, tmp_path, fsize=10)
    expect_refused(r, f"cannot write {out}: writing byte 10 of", "File too large")
    _assert_old_intact(tmp_path, [out])


STRACE_CASES = [("write-ENOSPC", ext) for ext in FORMATS] + \
               [("write-EDQUOT", "png"), ("write-EIO", "png"), ("fsync-EIO", "png"), ("fsync-ENOSPC", "jpg"),
                ("fsync-EIO", "exr"), ("rename-EROFS", "png"), ("faces-rename-EIO", "png"), ("faces-write-ENOSPC", "png")]


@pytest.mark.skipif(not STRACE, reason="strace (a test oracle) is not installed")
@pytest.mark.parametrize("fault,ext", STRACE_CASES, ids=[f"{f}-{e}" for f, e in STRACE_CASES])
@pytest.mark.why
def test_injected_system_call_faults(cli, files, tmp_path, fault, ext):
    faces = fault.startswith("faces")
    args, outputs = _fault_target("faces" if faces else "convert", ext)
    call, err = fault.replace("faces-", "").split("-")
    # The k-th call of its kind fails: the first write is the temporary's (nothing else is written
    # before the error line); for a face set, the fourth face's write, or the third rename.
    when = {"write": 4 if faces else 1, "fsync": 1, "rename": 3 if faces else 1}[call]
    # (strace counts each system call apart: for a face set only renameat2, which moves old faces
    # aside, so that the roll-back's renameat is not hit too, a second fault.)
    syscall = ("renameat2" if faces else "rename,renameat,renameat2") if call == "rename" else call
    _old_files(tmp_path, outputs)
    full = ["convert", files["png"], outputs[0] if not faces else "{face}." + ext] + args
    r = run(cli, full, tmp_path, strace=["-e", f"trace={syscall}", "-e", f"inject={syscall}:error={err}:when={when}"])
    assert f"{err}" in r.trace and "(INJECTED)" in r.trace, r.trace[-2000:]
    reason = os.strerror(getattr(__import__("errno"), err))
    expect_refused(r, "cannot write ", reason)
    _assert_old_intact(tmp_path, outputs)


def _tmpfs_available():
    if not shutil.which("unshare"):
        return False
    return subprocess.run(["unshare", "-rm", "sh", "-c", "mount -t tmpfs -o size=64k tmpfs /mnt"],
                          capture_output=True).returncode == 0


@pytest.mark.skipif(not _tmpfs_available(), reason="no tmpfs mount permitted here")
@pytest.mark.parametrize("kind", ["convert", "faces"])
@pytest.mark.why
def test_full_tmpfs(cli, files, tmp_path, kind):
    # A 1 MiB tmpfs holding the old outputs; the new ones do not fit.
    ext = "png"
    args, outputs = _fault_target(kind, ext)
    args = [a if a not in ("192x192", "64x64") else ("1024x1024" if kind == "convert" else "512x512") for a in args]
    noise = tmp_path / "noise.png"  # incompressible: the outputs cannot fit 1 MiB
    pp.write(str(noise), np.random.default_rng(1).integers(0, 256, (512, 1024, 3), np.uint8))
    mnt = tmp_path / "mnt"
    mnt.mkdir()
    target = outputs[0] if kind == "convert" else "{face}.png"
    script = (f"mount -t tmpfs -o size=1m tmpfs {mnt} && cd {mnt} && "
              + " && ".join(f"printf 'old {o}' > {o}" for o in outputs)
              + f" && {os.path.abspath(cli)} convert {noise} '{target}' {' '.join(args)}; echo \"rc=$?\";"
              + " for f in * .[!.]*; do [ -e \"$f\" ] && printf '%s:%s\\n' \"$f\" \"$(cat \"$f\" | head -c 40)\"; done; true")
    p = subprocess.run(["unshare", "-rm", "sh", "-c", script], capture_output=True, text=True, errors="replace",
                       timeout=120)
    assert "rc=1" in p.stdout, p.stdout + p.stderr
    assert "No space left on device" in p.stderr, p.stderr
    err_lines = [l for l in p.stderr.splitlines() if l.strip()]
    assert len(err_lines) == 1 and err_lines[0].startswith("panoproj: error: cannot write "), err_lines
    left = sorted(l for l in p.stdout.splitlines() if ":" in l)
    assert left == sorted(f"{o}:old {o}" for o in outputs), left


def test_a_folder_without_write_permission(cli, files):
    # As root the permission is dropped to nobody's (setpriv); otherwise the folder is made
    # read-only. The folders are outside pytest's (which only root may enter).
    import tempfile
    base = pathlib.Path(tempfile.mkdtemp(prefix="panoproj-perm-"))
    try:
        base.chmod(0o755)
        shutil.copy(files["png"], base / "in.png")
        (base / "in.png").chmod(0o644)
        folder = base / "ro"
        folder.mkdir()
        (folder / "o.png").write_bytes(b"old")
        command = os.path.abspath(native_command(cli))  # (a wheel's launcher: its interpreter may be root's)
        args = [command, "convert", str(base / "in.png"), str(folder / "o.png"), "--to", "fisheye",
                "--size", "32x32", "--overwrite"]
        if os.geteuid() == 0:
            if not runs_as_nobody(command):
                pytest.skip("root without setpriv, or the command cannot start as user nobody")
            folder.chmod(0o755)
            args = ["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups"] + args
        else:
            folder.chmod(0o555)
        p = subprocess.run(args, capture_output=True, text=True, timeout=60)
        folder.chmod(0o755)
        assert p.returncode == 1, p.stderr
        lines = p.stderr.strip().splitlines()
        assert len(lines) == 1 and f"cannot write {folder / 'o.png'}" in lines[0] and "Permission denied" in lines[0], \
            lines
        assert (folder / "o.png").read_bytes() == b"old" and listing(folder) == ["o.png"]
    finally:
        shutil.rmtree(base)


@pytest.mark.skipif(not _tmpfs_available(), reason="no tmpfs mount permitted here")
def test_a_read_only_file_system(cli, files, tmp_path):
    mnt = tmp_path / "mnt"
    mnt.mkdir()
    marker = '{"made_by": "panoproj"}'
    script = (f"mount -t tmpfs -o ro tmpfs {mnt} && {os.path.abspath(cli)} convert {files['png']} {mnt}/o.png "
              f"--to fisheye --size 32x32; echo \"rc=$?\"; ls -A {mnt}")
    p = subprocess.run(["unshare", "-rm", "sh", "-c", script], capture_output=True, text=True, timeout=60)
    assert "rc=1" in p.stdout and p.stdout.strip().endswith("rc=1"), p.stdout  # nothing listed after
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "cannot write" in lines[0] and "Read-only file system" in lines[0], lines


# ---------------------------------------------------------------------------------------------
# 5. Signals during a write: the temporary is removed, the old file intact.

@pytest.mark.skipif(not STRACE, reason="strace (a test oracle) is not installed")
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM, signal.SIGHUP], ids=["INT", "TERM", "HUP"])
@pytest.mark.parametrize("kind", ["convert", "faces"])
@pytest.mark.why
def test_signals_during_a_write_leave_nothing_behind(cli, files, tmp_path, sig, kind):
    args, outputs = _fault_target(kind, "png")
    _old_files(tmp_path, outputs)
    full = ["convert", files["png"], outputs[0] if kind == "convert" else "{face}.png"] + args

    # strace holds the first fsync for 3 s: the temporary exists then.
    r = run(cli, full, tmp_path, strace=["-e", "trace=fsync", "-e", "inject=fsync:delay_enter=3000000:when=1"],
            on_start=_signal_once_a_temporary_exists(tmp_path, sig, 0.3))
    assert r.code in (-sig, 128 + sig), (r.code, r.err)
    _assert_old_intact(tmp_path, outputs)


def _signal_once_a_temporary_exists(folder, sig, pause):
    """on_start for run(): signals the tracee (strace's child) `pause` s after a temporary appears."""
    def interrupt(p):
        deadline = time.time() + 20
        while time.time() < deadline:
            kids = _children(p.pid)
            if kids and any(n.startswith(".panoproj-") for n in os.listdir(folder)):
                time.sleep(pause)
                os.kill(kids[0], sig)
                return
            time.sleep(0.05)
    return lambda p: threading.Thread(target=interrupt, args=(p,), daemon=True).start()


def _children(pid):
    try:
        with open(f"/proc/{pid}/task/{pid}/children") as f:
            return [int(x) for x in f.read().split()]
    except OSError:
        return []


# ---------------------------------------------------------------------------------------------
# 6. The Python module: the same guarantees, Python's classes and wording.

def _python(code, *, fsize=None, timeout=60):
    """Runs code in a fresh interpreter (a fault must not end this one); returns (rc, out, err)."""
    def limits():
        if fsize is not None:
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
            resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, resource.RLIM_INFINITY))
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout,
                       preexec_fn=limits, env=dict(os.environ))
    return p.returncode, p.stdout, p.stderr


@pytest.mark.parametrize("ext", FORMATS)
@pytest.mark.why
def test_python_write_on_a_full_disk_raises_and_keeps_the_old_file(tmp_path, ext):
    path = tmp_path / f"x.{ext}"
    path.write_bytes(b"old")
    code = (f"import numpy as np, panoproj as pp\n"
            f"a = np.full((64, 64, 3), 0.5, np.float32) if '{ext}' in ('exr', 'hdr') else np.full((64, 64, 3), 9, np.uint8)\n"
            f"try:\n    pp.write({str(path)!r}, a, overwrite=True)\n"
            f"except OSError as e:\n    print('OSError', e)\nprint('alive')\n")
    rc, out, err = _python(code, fsize=20)
    assert rc == 0 and "alive" in out, (rc, out, err)
    assert f"OSError cannot write {path}: writing byte 20 of" in out and "File too large" in out, out
    assert path.read_bytes() == b"old"
    assert listing(tmp_path) == [f"x.{ext}"]


@pytest.mark.why
def test_python_write_checks_a_face_patterns_array(tmp_path):
    with pytest.raises(ValueError, match=r"cube faces: a 300x256 image \(expected the 6x1 strip"):
        pp.write(str(tmp_path / "{face}.png"), np.zeros((256, 300, 3), np.uint8))
    assert listing(tmp_path) == []


@pytest.mark.parametrize("case", ["exists", "dangling", "directory", "missing_folder"])
def test_python_write_refusals(tmp_path, case):
    img = np.zeros((8, 8, 3), np.uint8)
    p = tmp_path / "x.png"
    if case == "exists":
        p.write_bytes(b"old")
        with pytest.raises(FileExistsError, match=r"x\.png exists \(pass overwrite=True to replace it\)"):
            pp.write(str(p), img)
        assert p.read_bytes() == b"old"
    elif case == "dangling":
        os.symlink(tmp_path / "nowhere", p)
        with pytest.raises(FileExistsError, match="a link"):
            pp.write(str(p), img)
    elif case == "directory":
        p.mkdir()
        with pytest.raises(OSError, match="is a directory"):
            pp.write(str(p), img, overwrite=True)
    else:
        with pytest.raises(FileNotFoundError, match="output folder"):
            pp.write(str(tmp_path / "nowhere" / "x.png"), img)


@pytest.mark.parametrize("kw, error, needle", [
    (dict(quality=0), ValueError, "quality: 0 \\(expected 1 to 100\\)"),
    (dict(quality=101), ValueError, "quality: 101"),
    (dict(quality="high"), TypeError, "quality: 'high' \\(expected an integer"),
    (dict(quality=True), TypeError, "quality: True"),
    (dict(subsampling="411"), ValueError, "subsampling 411 \\(expected 420, 422 or 444\\)"),
    (dict(subsampling=None), ValueError, "subsampling None"),
], ids=["quality_0", "quality_101", "quality_text", "quality_bool", "subsampling_411", "subsampling_none"])
def test_python_write_option_refusals(tmp_path, kw, error, needle):
    with pytest.raises(error, match=needle):
        pp.write(str(tmp_path / "x.jpg"), np.zeros((8, 8, 3), np.uint8), **kw)
    assert listing(tmp_path) == []


@pytest.mark.parametrize("case", ["same", "view", "overlap"])
@pytest.mark.why
def test_plan_run_refuses_an_out_that_shares_the_images_memory(case):
    img = smooth_equirect(128, 64)
    plan = pp.Plan("equirect", "equirect", (128, 64))
    big = np.zeros((128, 128, 3), np.uint8)
    if case == "same":
        src, out = img, img
    elif case == "view":
        src, out = big[:64], big[:64]
    else:
        src, out = big[:64], big[32:96]
    src[...] = img
    with pytest.raises(ValueError, match="out: shares memory with the image"):
        plan.run(src, out=out)


PY_IMG = "np.zeros((32, 64, 3), np.uint8)"
PONDS = str(pathlib.Path(__file__).resolve().parents[2] / "samples" / "images" / "jordan_pond_4096x2048.jpg")
PY_CALLS = [
    # (id, call, exception class, needle, why); each runs in a fresh interpreter (earlier code
    # crashed on some: a segfault must not end the suite).
    ("convert_2e32", f"pp.convert({PY_IMG}, 'equirect', 'fisheye', size=(2**32, 2**32))", "ValueError",
     "4294967296x4294967296", True),
    ("convert_huge", f"pp.convert({PY_IMG}, 'equirect', 'fisheye', size=(2**31 - 1, 2**31 - 1))", "MemoryError",
     "over the memory limit", False),
    ("convert_limit", f"pp.convert({PY_IMG}, 'equirect', 'fisheye', size=(4000, 4000), memory_limit='10M')",
     "MemoryError", "memory_limit=", False),
    ("convert_photometry_wb", f"pp.convert({PY_IMG}, 'equirect:wb=0/1', 'fisheye')", "ValueError",
     "white balance Er0", False),
    ("plan_photometry_vignetting", f"pp.Plan('equirect:vignetting=1/-2', 'fisheye', {PY_IMG}.shape[1::-1])",
     "ValueError", "inside the image", False),
    ("build_map_photometry", "pp.build_map('fisheye:ev=1', 'equirect', (64, 64))", "ValueError",
     "maps: photometric keys", False),
    ("build_map_2e32", "pp.build_map('equirect', 'fisheye', (64, 32), size=(2**32, 2**32))", "ValueError",
     "4294967296x4294967296", True),
    ("build_map_huge", "pp.build_map('equirect', 'fisheye', (64, 32), size=(100000, 100000))", "MemoryError",
     "map 100000x100000 needs 160 GB", False),
    ("plan_huge", "pp.Plan('equirect', 'fisheye', (64, 32), size=(1 << 30, 1 << 30))", "MemoryError", "needs", False),
    # convert fits 12 MB; a plan also keeps up to 17 bytes a pixel for its later runs (kept taps)
    ("plan_kept_limit", f"pp.Plan('equirect', 'pinhole', (64, 32), size=(1000, 1000), memory_limit='12M')({PY_IMG})",
     "MemoryError", "with the maps and taps the plan keeps", False),
    ("size_2e70", f"pp.convert({PY_IMG}, 'equirect', 'fisheye', size=(2**70, 1))", "ValueError",
     "size: 1180591620717411303424x1", True),
    ("threads_2e70", f"pp.convert({PY_IMG}, 'equirect', 'fisheye', threads=2**70)", "ValueError",
     "threads: 1180591620717411303424", True),
    ("threads_text", f"pp.convert({PY_IMG}, 'equirect', 'fisheye', threads='many')", "TypeError", "threads: 'many'",
     False),
    ("yaw_1e400", f"pp.convert({PY_IMG}, 'equirect', 'fisheye', yaw=10**400)", "ValueError", "yaw:", False),
    ("unknown_option", f"pp.convert({PY_IMG}, 'equirect', 'fisheye', zoom=2)", "TypeError",
     "convert: unknown option 'zoom'", False),
    ("plan_maps_only_option", "pp.Plan('equirect', 'fisheye', (64, 32), convention='opencv')", "TypeError",
     "unknown option 'convention'", False),
    ("interp_not_text", f"pp.convert({PY_IMG}, 'equirect', 'fisheye', interp=3)", "TypeError", "interp: 3 (expected text)",
     False),
    ("size_text_pair", f"pp.convert({PY_IMG}, 'equirect', 'fisheye', size=('a', 'b'))", "TypeError", "size:", False),
    ("memory_limit_text", f"pp.convert({PY_IMG}, 'equirect', 'fisheye', memory_limit='lots')", "ValueError",
     "memory limit: lots", False),
    ("memory_limit_tiny", f"pp.convert({PY_IMG}, 'equirect', 'fisheye', memory_limit=5)", "ValueError",
     "memory_limit: 5", False),
    ("image_not_array", "pp.convert(b'not an image', 'equirect', 'fisheye')", "TypeError", "image", False),
    ("image_path_missing", "pp.convert('not an image', 'equirect', 'fisheye')", "FileNotFoundError",
     "input not an image does not exist", False),
    ("write_not_array", "pp.write('/tmp/never-written.png', 'pixels')", "TypeError", "array: str", True),
    ("to_ray_text", "pp.to_ray('pinhole', (10, 10), 'a', 'b')", "Exception", "", False),
    ("src_wording", "pp.convert(np.zeros((33, 64, 3), np.uint8), None, 'fisheye')", "ValueError", "give src", False),
    ("overwrite_wording", "open('/tmp/pp-exists.png', 'wb').close(); pp.write('/tmp/pp-exists.png', "
                          "np.zeros((4, 4, 3), np.uint8))", "FileExistsError", "overwrite=True", True),
    ("read_limit", f"pp.read({PONDS!r}, memory_limit='10M')", "MemoryError", "memory_limit=", False),
    ("faces_strip", "pp.write('/tmp/pp-never-{face}.png', np.zeros((256, 300, 3), np.uint8))", "ValueError",
     "300x256", True),
    # arrays as users hold them, conventions, panoproj.compat
    ("batch_huge", "pp.convert(np.broadcast_to(np.zeros((1, 64, 128, 3), np.uint8), (10**7, 64, 128, 3)), 'equirect', "
                   "'pinhole', size=(64, 64))", "MemoryError", "batch output 10000000 x 64x64x3 needs", False),
    ("batch_empty", "pp.convert(np.zeros((0, 64, 128, 3), np.uint8), 'equirect', 'pinhole')", "ValueError",
     "(0, 64, 128, 3): empty", False),
    ("channels_first", "pp.convert(np.zeros((3, 64, 128), np.uint8), 'equirect', 'pinhole')", "ValueError",
     "channels first (CHW)", False),
    ("six_dims", "pp.convert(np.zeros((1, 1, 1, 64, 128, 3), np.uint8), 'equirect', 'pinhole')", "ValueError",
     "6 dimensions", False),
    ("labels_interpolated", "pp.convert(np.zeros((64, 128), np.int32), 'equirect', 'pinhole')", "TypeError",
     "interp='nearest'", False),
    ("labels_alpha", "pp.convert(np.zeros((64, 128), np.int32), 'equirect', 'pinhole', interp='nearest', alpha=True)",
     "ValueError", "alpha: this int32 image", False),
    ("nearest_antialias", f"pp.convert({PY_IMG}, 'equirect', 'pinhole', interp='nearest', antialias='mip')",
     "ValueError", "antialias='mip' with interp='nearest'", False),
    ("object_dtype", "pp.convert(np.zeros((64, 128), object), 'equirect', 'pinhole')", "TypeError",
     "array dtype object", False),
    ("bad_dlpack", "pp.convert(type('X', (), {'__dlpack__': lambda s, **k: 1})(), 'equirect', 'pinhole')",
     "TypeError", "numpy cannot read", False),
    ("faces_dict_keys", "pp.convert({'F': np.zeros((8, 8), np.uint8)}, 'cubemap', 'equirect')", "ValueError",
     "cube faces: keys ['F']", False),
    ("faces_five", "pp.convert([np.zeros((8, 8), np.uint8)] * 5, 'cubemap', 'equirect')", "ValueError",
     "5 arrays (expected 6", False),
    ("convention_bad", "pp.to_pixel('equirect', (8, 4), [[0, 0, 1]], convention='cv')", "ValueError",
     "convention: 'cv'", False),
    ("torch_map_huge", "pp.build_map('equirect', 'fisheye', (64, 32), size=(100000, 100000), convention='torch')",
     "MemoryError", "needs", False),
    ("projection_typo", f"pp.convert({PY_IMG}, 'equirect', 'perspective')", "ValueError", "did you mean pinhole?", False),
    ("key_not_number", "pp.Fisheye(fov=[180])", "TypeError", "fov: [180]", False),
    ("key_nan", "pp.Fisheye(fov=float('nan'))", "ValueError", "fov=nan is not finite", False),
    ("compat_face_w_nan", "from panoproj import compat; compat.e2c(np.zeros((64, 128, 3), np.uint8), float('nan'))", "TypeError", "face_w: nan",
     False),
    ("compat_face_w_huge", "from panoproj import compat; compat.e2c(np.zeros((64, 128, 3), np.uint8), 2**20)", "MemoryError", "needs", False),
    ("compat_face_w_zero", "from panoproj import compat; compat.e2c(np.zeros((64, 128, 3), np.uint8), 0)", "ValueError", "face_w: 0", False),
    ("compat_c2e_huge", "from panoproj import compat; compat.c2e([np.zeros((8, 8, 3), np.uint8)] * 6, 2**20, 2**21, cube_format='list')",
     "MemoryError", "needs", False),
    ("compat_mode", "from panoproj import compat; compat.e2p(np.zeros((64, 128, 3), np.uint8), 90, 0, 0, (8, 8), mode='quintic')", "ValueError",
     "mode: 'quintic'", False),
    ("compat_fov_nan", "from panoproj import compat; compat.e2p(np.zeros((64, 128, 3), np.uint8), float('nan'), 0, 0, (8, 8))", "ValueError",
     "fov_deg: nan", False),
    ("compat_fov_180", "from panoproj import compat; compat.e2p(np.zeros((64, 128, 3), np.uint8), (90, 180), 0, 0, (8, 8))", "ValueError",
     "fov_deg: 180", False),
    ("compat_c2e_faces", "from panoproj import compat; compat.c2e([np.zeros((8, 8, 3), np.uint8)] * 5 + [np.zeros((8, 8), np.uint8)], 8, 16, "
     "cube_format='list')", "ValueError", "face D is (8, 8) uint8", False),
    ("compat_out_hw", "from panoproj import compat; compat.e2p(np.zeros((64, 128, 3), np.uint8), 90, 0, 0, '8x8')", "TypeError", "out_hw: '8x8'",
     False),
    ("compat_u_inf", "from panoproj import compat; compat.e2p(np.zeros((64, 128, 3), np.uint8), 90, float('inf'), 0, (8, 8))", "ValueError", "yaw: inf",
     False),
    ("compat_dice_shape", "from panoproj import compat; compat.c2e(np.zeros((10, 10, 3), np.uint8), 8, 16)", "ValueError", "cube_format='dice'", False),
]


@pytest.mark.parametrize("case", _table(PY_CALLS))
def test_python_sizes_types_and_wording(case):
    name, call, cls, needle, _ = case
    code = (f"import numpy as np, panoproj as pp\ntry:\n    {call}\n    print('no error')\n"
            f"except {cls} as e:\n    print(type(e).__name__ + ': ' + str(e).replace(chr(10), '<NL>'))\n")
    rc, out, err = _python(code, timeout=60)
    assert rc == 0, f"the interpreter ended: {rc} {err[-500:]}"
    text = out.strip()
    assert "<NL>" not in text and "incompatible function arguments" not in text and "bad_alloc" not in text, text
    assert text != "no error" and needle in text, text
    assert "--" not in text, text  # Python wording, not the command's


PY_READS = [("fifo", OSError, "a FIFO"), ("dir", OSError, "a directory"), ("devzero", OSError, "a device"),
            ("zero", OSError, "a device"), ("patched_jpeg", OSError, "too few to hold them"),
            ("huge_tiff", OSError, "too few to hold them"), ("garbage", OSError, "not a JPEG"),
            ("missing", FileNotFoundError, "does not exist")]


@pytest.mark.parametrize("case", PY_READS, ids=[c[0] for c in PY_READS])
def test_python_reads_of_hostile_files(files, case):
    key, cls, needle = case
    path = files[key] if key != "missing" else "/nonexistent/x.png"
    # (the peak since its exec, VmHWM in kB: a child forked from a worker that has grown starts
    # with the worker's as its ru_maxrss)
    code = (f"import panoproj as pp\n"
            f"try:\n    pp.read({str(path)!r})\nexcept {cls.__name__} as e:\n    print(type(e).__name__, e)\n"
            f"print([int(l.split()[1]) for l in open('/proc/self/status') if l.startswith('VmHWM')][0])\n")
    rc, out, err = _python(code, timeout=30)
    assert rc == 0, err
    first, rss = out.strip().splitlines()
    assert first.startswith(cls.__name__) and needle in first, first
    assert int(rss) * 1024 < HOSTILE_RSS


def test_nan_and_inf_pixels_have_defined_integers(tmp_path):
    img = np.full((32, 64, 3), 0.5, np.float32)
    img[:, :8] = np.nan
    img[:, 8:16] = np.inf
    img[:, 16:24] = -np.inf
    with pytest.warns(UserWarning, match=r"samples clipped: .*: 2304 samples"):  # the NaN and inf columns
        pp.write(str(tmp_path / "n.png"), img, dtype="uint8")
    back = pp.read(str(tmp_path / "n.png"))
    assert (back[:, :8] == 0).all() and (back[:, 8:16] == 255).all() and (back[:, 16:24] == 0).all()
    assert (back[:, 32:] == 128).all()
    # A non-finite sample makes every output sample whose kernel support holds it non-finite
    # (NaN where it meets a zero weight: inf x 0), across the seam and the poles too; no further.
    out = pp.convert(img, "equirect", "equirect", interp="bilinear", antialias="off")
    assert not np.isfinite(out[1:-1, :24]).any() and np.isnan(out[1:-1, 63]).all()
    assert np.isfinite(out[1:-1, 24:62]).all()


# ---------------------------------------------------------------------------------------------
# 7. Tile pyramids (panoproj tiles, pp.tiles): the output is a folder that lands whole.

TILE_PARAMS = [
    # (id, args after "tiles IN out", needle, input key)
    ("viewer", ["--viewer", "krpano"], "viewer krpano is not known (use pannellum or marzipano)", "png"),
    ("tile_8", ["--tile", "8"], "--tile 8 is out of range (16 to 8192 px)", "png"),
    ("tile_text", ["--tile", "big"], "--tile", "png"),
    ("levels_99", ["--levels", "99"], "--levels 99 is out of range", "png"),
    ("levels_too_many", ["--levels", "9"], "--levels 9: a 80 px face in 80 px tiles has 1 level (use at most that)", "png"),
    ("cube_size_marzipano", ["--viewer", "marzipano", "--cube-size", "1000"], "--cube-size 1000 is not 512 x 2^k", "png"),
    ("cube_size_huge", ["--cube-size", "99999999999"], "--cube-size 99999999999 is out of range", "png"),
    ("cube_size_past_the_detail", ["--cube-size", "4096"], "--cube-size 4096 is over 4x the source's resolution", "png"),
    ("format", ["--format", "webp"], "--format webp is not a format web viewers show (use jpg or png)", "png"),
    ("quality", ["--quality", "0"], "quality: 0 (expected 1 to 100)", "png"),
    ("preview", ["--preview", "99999"], "--preview 99999 is out of range", "png"),
    ("preview_marzipano", ["--viewer", "marzipano", "--preview", "100"], "--preview 100 does not divide", "png"),
    ("script_url_quote", ["--script-url", 'x"><script>'], "has a character a page cannot hold in an attribute", "png"),
    ("decode_scale", ["--decode-scale", "2"], "--decode-scale 2: each level takes its own scale (use auto or 1)", "jpg"),
    ("yaw_nan", ["--yaw", "nan"], "yaw: nan (expected a finite angle", "png"),
    ("threads", ["--threads", "-5"], "threads: -5", "png"),
    ("memory_limit", ["--memory-limit", "1M"], "a band of tiles needs 2.7 MB, over the memory limit of 1.0 MB", "big"),
    ("size_is_not_a_tiles_option", ["--size", "64x64"], "--size", "png"),
    ("stereo", ["--from", "equirect:stereo=tb"], "tiles: stereo=", "png"),
    ("no_projection", [], "cannot tell the projection", "square"),
]


@pytest.fixture
def square(tmp_path):
    path = tmp_path / "square.png"
    pp.write(str(path), smooth_equirect(64, 64))
    return path


@pytest.mark.parametrize("case", TILE_PARAMS, ids=[c[0] for c in TILE_PARAMS])
def test_tiles_bad_parameters(cli, files, tmp_path, case, square):
    _, args, needle, key = case
    src = square if key == "square" else files[key]
    before = snapshot(tmp_path)
    r = run(cli, ["tiles", src, "out"] + args, tmp_path)
    expect_refused(r, needle)
    assert r.out == ""
    assert snapshot(tmp_path) == before


MARKER = "panoproj-output.json"


def _old_folder(tmp_path, name="out"):
    """A folder an earlier run made (its marker at the root), with a file the user added."""
    (tmp_path / name).mkdir()
    (tmp_path / name / MARKER).write_text('{"made_by": "panoproj", "job": "tiles"}\n')
    (tmp_path / name / "mine.txt").write_bytes(b"old")


def _assert_old_folder(tmp_path):
    assert listing(tmp_path) == ["out"], listing(tmp_path)  # no temporary folder left beside it
    assert listing(tmp_path / "out") == ["mine.txt", MARKER] and (tmp_path / "out" / "mine.txt").read_bytes() == b"old"


# The folder jobs (tiles, views) land the same way: these cases run for both.
FOLDER_JOBS = {"tiles": {"config.json", "index.html", "fallback", "1", MARKER},
               "views": {"images", "sparse", "transforms.json", MARKER}}


@pytest.mark.parametrize("command", FOLDER_JOBS)
@pytest.mark.parametrize("case", _table(HOSTILE))
def test_folder_hostile_inputs(cli, files, tmp_path, case, command):
    key, needle, _ = case
    before = snapshot(tmp_path)
    small = ["--size", "32x32"] if command == "views" else []
    r = run(cli, [command, files[key], "out", "--from", "equirect"] + small, tmp_path, timeout=30)
    line = expect_refused(r, needle, rss=HOSTILE_RSS)
    assert str(files[key]) in line
    assert snapshot(tmp_path) == before


@pytest.mark.parametrize("command", FOLDER_JOBS)
@pytest.mark.parametrize("case", ["exists", "file", "missing_folder"])
def test_folder_outputs_that_cannot_be_written(cli, files, tmp_path, case, command):
    out = {"exists": "out", "file": "afile", "missing_folder": "nowhere/out"}[case]
    if case == "exists":
        _old_folder(tmp_path)
    (tmp_path / "afile").write_bytes(b"a file")
    before = snapshot(tmp_path)
    r = run(cli, [command, files["png"], out], tmp_path)
    expect_refused(r, {"exists": "output out exists (pass --overwrite to replace the folder)",
                       "file": "output afile exists and is not a folder",
                       "missing_folder": "output folder nowhere does not exist"}[case])
    assert snapshot(tmp_path) == before


@pytest.mark.parametrize("command", FOLDER_JOBS)
def test_folder_input_inside_the_output_is_refused(cli, files, tmp_path, command):
    # --overwrite replaces the folder: an input inside it would be deleted with it.
    _old_folder(tmp_path)
    (tmp_path / "out" / "in.png").write_bytes(files["png"].read_bytes())
    before = snapshot(tmp_path)
    r = run(cli, [command, tmp_path / "out" / "in.png", "out", "--overwrite"], tmp_path)
    expect_refused(r, "is inside the output folder out")
    assert snapshot(tmp_path) == before


@pytest.mark.parametrize("command", FOLDER_JOBS)
def test_folder_overwrite_replaces_the_whole_folder(cli, files, tmp_path, command):
    _old_folder(tmp_path)
    r = run(cli, [command, files["png"], "out", "--overwrite", "-q"], tmp_path)
    assert r.code == 0, r.err
    assert listing(tmp_path) == ["out"]
    names = listing(tmp_path / "out")
    assert "mine.txt" not in names and FOLDER_JOBS[command] <= set(names)


@pytest.mark.parametrize("command", FOLDER_JOBS)
@pytest.mark.parametrize("cut", [0, 3000, 30000])
def test_folder_writes_cut_at_a_byte_offset(cli, files, tmp_path, cut, command):
    # RLIMIT_FSIZE: the first file past `cut` bytes fails (EFBIG); the old folder stays, nothing is left.
    _old_folder(tmp_path)
    r = run(cli, [command, files["big"], "out", "--overwrite", "--format", "png"], tmp_path, fsize=cut)
    expect_refused(r, "cannot write ", "File too large")
    _assert_old_folder(tmp_path)


@pytest.mark.skipif(not _tmpfs_available(), reason="no tmpfs mount permitted here")
@pytest.mark.parametrize("command", FOLDER_JOBS)
def test_folder_on_a_full_tmpfs(cli, files, tmp_path, command):
    mnt = tmp_path / "mnt"
    mnt.mkdir()
    marker = '{"made_by": "panoproj"}'
    script = (f"mount -t tmpfs -o size=1m tmpfs {mnt} && cd {mnt} && mkdir out && printf old > out/mine.txt && printf '{marker}' > out/{MARKER} && "
              f"{os.path.abspath(cli)} {command} {files['big']} out --overwrite --format png; echo \"rc=$?\"; "
              f"ls -A {mnt}; ls -A {mnt}/out; cat {mnt}/out/mine.txt")
    p = subprocess.run(["unshare", "-rm", "sh", "-c", script], capture_output=True, text=True, timeout=120)
    assert "rc=1" in p.stdout, p.stdout + p.stderr
    assert p.stdout.split("rc=1")[1].split() == ["out", "mine.txt", MARKER, "old"], p.stdout
    lines = [l for l in p.stderr.splitlines() if l.strip()]
    assert len(lines) == 1 and "cannot write" in lines[0] and "No space left on device" in lines[0], lines


@pytest.mark.skipif(not STRACE, reason="strace (a test oracle) is not installed")
@pytest.mark.parametrize("command", FOLDER_JOBS)
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["INT", "TERM"])
def test_folder_signals_leave_nothing_behind(cli, files, tmp_path, sig, command):
    # strace holds the one syncfs for 3 s: every file is in the temporary folder then.
    _old_folder(tmp_path)
    r = run(cli, [command, files["big"], "out", "--overwrite"], tmp_path,
            strace=["-e", "trace=syncfs", "-e", "inject=syncfs:delay_enter=3000000:when=1"],
            on_start=_signal_once_a_temporary_exists(tmp_path, sig, 0.5))
    assert r.code in (-sig, 128 + sig), (r.code, r.err)
    _assert_old_folder(tmp_path)


@pytest.mark.parametrize("command", FOLDER_JOBS)
def test_python_folder_job_on_a_client_that_fails_leaves_nothing(files, tmp_path, command):
    class Failing:  # a scheduler whose tasks fail
        def submit(self, *a, **k):
            raise RuntimeError("worker lost")

    with pytest.raises(RuntimeError, match="worker lost"):
        getattr(pp, command)(files["png"], tmp_path / "out", client=Failing())
    assert listing(tmp_path) == []


TILE_PY_CALLS = [
    ("exists", dict(), FileExistsError, "exists (pass overwrite=True to replace the folder)"),
    ("viewer", dict(viewer="krpano"), ValueError, "viewer krpano is not known"),
    ("tile_type", dict(tile="512"), TypeError, "tile: '512' (expected an int)"),
    ("levels_type", dict(levels=1.5), TypeError, "levels: 1.5 (expected an int)"),
    ("tile_range", dict(tile=8), ValueError, "tile='8' is out of range (16 to 8192 px)"),
    ("unknown_option", dict(size=(64, 64)), TypeError, "unknown option 'size'"),
    ("yaw_nan", dict(yaw=float("nan")), ValueError, "yaw: nan"),
    ("memory", dict(memory_limit="1M"), MemoryError, "over the memory limit"),
]



# ---------------------------------------------------------------------------------------------
# 8. Perspective views with cameras (panoproj views, pp.views): a folder that lands whole, every
# input checked before the first view is rendered.

VIEW_PARAMS = [
    # (id, args after "views IN", needle[, input key: default png])
    ("rig", ["--rig", "sphere"], "rig: 'sphere' (expected cube, ring:n=8,fov=90,pitch=0"),
    ("ring_n", ["--rig", "ring:n=1000"], "rig ring: n: 1000 (expected a whole number from 1 to 360)"),
    ("ring_fov", ["--rig", "ring:fov=180"], "hfov 180 (expected more than 0, at most 179 degrees"),
    ("ring_nan", ["--rig", "ring:pitch=nan"], "rig ring: pitch: 'nan' (expected a finite number)"),
    ("rig_file_missing", ["--rig", "@nowhere.yaml"], "the rig file nowhere.yaml does not exist (check the path)"),
    ("rig_file_fifo", ["--rig", "@fifo"], "cannot read the rig file fifo: a FIFO (expected a YAML list of views after @)"),
    ("rig_file_binary", ["--rig", "@binary.yaml"], "a NUL byte (expected YAML text)"),
    ("rig_file_huge", ["--rig", "@huge.yaml"], "over 1 MB"),
    ("rig_names_twice", ["--rig", "cube+cube"], "two views named front"),
    ("wide_at_the_source", ["--rig", "ring:fov=179"], "px wide at the source's resolution (at most 65536)", "big"),
    ("size_huge", ["--size", "70000x10"], "size: 70000x10 (expected 1 to 65536 pixels a side)"),
    ("size_and_vfov", ["--rig", "ring:vfov=40", "--size", "64x64"], "and a size 64x64 both given"),
    ("format", ["--format", "webp"], "--format webp is not a format web viewers show (use jpg or png)"),
    ("quality", ["--quality", "0"], "quality: 0 (expected 1 to 100)"),
    ("threads", ["--threads", "-5"], "threads: -5"),
    ("memory_limit", ["--memory-limit", "1M"], "over the memory limit of 1.0 MB", "big"),
    ("yaw_is_not_a_views_option", ["--yaw", "10"], "--yaw"),
    ("stereo", ["--from", "equirect:stereo=tb"], "views: stereo="),
]


@pytest.fixture
def rig_files(tmp_path):
    os.mkfifo(tmp_path / "fifo")
    (tmp_path / "binary.yaml").write_bytes(b"- {name: a}\n\0\n")
    (tmp_path / "huge.yaml").write_bytes(b"# x\n" * 300000)


@pytest.mark.parametrize("case", VIEW_PARAMS, ids=[c[0] for c in VIEW_PARAMS])
def test_views_bad_parameters(cli, files, tmp_path, case, rig_files):
    _, args, needle, *key = case
    before = snapshot(tmp_path)
    r = run(cli, ["views", files[key[0] if key else "png"], "out"] + args, tmp_path, timeout=30)
    expect_refused(r, needle)
    assert r.out == ""
    assert snapshot(tmp_path) == before


@pytest.mark.parametrize("case", ["two_sizes", "same_stem", "space_in_name"])
def test_views_inputs_a_rig_cannot_take(cli, files, tmp_path, case):
    (tmp_path / "b").mkdir()
    (tmp_path / "b" / "pano.png").write_bytes(files["png"].read_bytes())
    (tmp_path / "my pano.png").write_bytes(files["png"].read_bytes())
    second, needle = {"two_sizes": (files["big"], "a rig's frames need one size and projection"),
                      "same_stem": (tmp_path / "b" / "pano.png", "a second input named pano"),
                      "space_in_name": (tmp_path / "my pano.png", "which COLMAP's images.txt cannot hold")}[case]
    before = snapshot(tmp_path)
    r = run(cli, ["views", files["png"], second, "out", "--overwrite"], tmp_path)
    expect_refused(r, needle)
    assert snapshot(tmp_path) == before


VIEW_PY_CALLS = [
    ("exists", dict(), FileExistsError, "exists (pass overwrite=True to replace the folder)"),
    ("rig_type", dict(rig=5), TypeError, "rig: 5 (expected a str such as 'cube', or a sequence of mappings)"),
    ("rig_view_type", dict(rig=["front"]), TypeError, "rig[0]: 'front' (expected a mapping"),
    ("rig_key", dict(rig=[{"name": "a", "zoom": 2}]), TypeError, "rig[0]: unknown key 'zoom'"),
    ("rig_yaw_type", dict(rig=[{"name": "a", "yaw": "10"}]), TypeError, "rig[0]['yaw']: '10' (expected a number"),
    ("rig_yaw_nan", dict(rig=[{"name": "a", "yaw": float("nan")}]), ValueError, "rig[0]['yaw']: nan"),
    ("rig_name_yaml", dict(rig=[{"name": "a: b"}]), ValueError, "rig[0]['name']: 'a: b'"),
    ("rig_name_path", dict(rig=[{"name": "../a"}]), ValueError, "name '../a' (expected 1 to 64 letters"),
    ("rig_empty", dict(rig=[]), ValueError, "rig: no views"),
    ("images_type", dict(images=5), TypeError, "images: 5 (expected a path or a sequence of paths)"),
    ("no_images", dict(images=[]), ValueError, "no input given"),
    ("size_text", dict(size="64y"), ValueError, "size: '64y' (expected WxH, e.g. 4096x2048, or N for a square)"),
    ("unknown_option", dict(yaw=10), TypeError, "unknown option 'yaw'"),
    ("memory", dict(memory_limit="1M"), MemoryError, "over the memory limit"),
]


PY_FOLDER_CALLS = [("tiles",) + c for c in TILE_PY_CALLS] + [("views",) + c for c in VIEW_PY_CALLS]


@pytest.mark.parametrize("case", PY_FOLDER_CALLS, ids=[f"{c[0]}-{c[1]}" for c in PY_FOLDER_CALLS])
def test_python_folder_job_refusals(files, tmp_path, case):
    command, name, kw, error, needle = case
    if name == "exists":
        _old_folder(tmp_path)
    before = snapshot(tmp_path)
    kw = dict(kw)
    images = kw.pop("images", files["big"])
    with pytest.raises(error, match=re.escape(needle)):
        getattr(pp, command)(images, tmp_path / "out", **kw)
    assert snapshot(tmp_path) == before


# ---------------------------------------------------------------------------------------------
# 9. Output folders reached only through opened folders, identities by device and inode, no
#    removal into mounts, --overwrite only on panoproj's folders, stale
#    temporaries, degenerate geometry, Python's copies and Ctrl-C, memory limits, HDR in bands.

def _earlier_layout(tmp_path, command):
    """A folder as the version before the marker wrote it (no marker)."""
    out = tmp_path / "out"
    if command == "tiles":
        for d in ("1", "fallback"):
            (out / d).mkdir(parents=True)
        (out / "config.json").write_text("{}")
        (out / "index.html").write_text("<html>")
        (out / "1" / "f0_0.jpg").write_bytes(b"old tile")
    else:
        (out / "images").mkdir(parents=True)
        (out / "sparse" / "0").mkdir(parents=True)
        (out / "transforms.json").write_text("{}")
        (out / "images" / "a_front.jpg").write_bytes(b"old view")


@pytest.mark.parametrize("command", FOLDER_JOBS)
def test_overwrite_refuses_a_folder_panoproj_did_not_make(cli, files, tmp_path, command):
    (tmp_path / "photos").mkdir()
    (tmp_path / "photos" / "holiday.jpg").write_bytes(b"irreplaceable")
    before = snapshot(tmp_path)
    t0 = time.perf_counter()
    r = run(cli, [command, files["big"], "photos", "--overwrite"], tmp_path)
    expect_refused(r, "output photos was not made by panoproj (no panoproj-output.json, not a tile pyramid or view set)",
                   "give a new folder's name, or remove it yourself")
    assert time.perf_counter() - t0 < 5  # before any work
    assert snapshot(tmp_path) == before and (tmp_path / "photos" / "holiday.jpg").read_bytes() == b"irreplaceable"


@pytest.mark.parametrize("command", FOLDER_JOBS)
@pytest.mark.parametrize("made_by", ["marker", "earlier_layout", "empty"])
def test_overwrite_replaces_a_folder_panoproj_made(cli, files, tmp_path, command, made_by):
    if made_by == "marker":
        _old_folder(tmp_path)
    elif made_by == "earlier_layout":
        _earlier_layout(tmp_path, command)
    else:
        (tmp_path / "out").mkdir()
    r = run(cli, [command, files["png"], "out", "--overwrite", "-q"], tmp_path)
    assert r.code == 0, r.err
    assert listing(tmp_path) == ["out"]
    names = set(listing(tmp_path / "out"))
    assert FOLDER_JOBS[command] <= names and "mine.txt" not in names
    assert json.loads((tmp_path / "out" / MARKER).read_text()) == {"made_by": "panoproj", "job": command}


@pytest.mark.parametrize("command", FOLDER_JOBS)
@pytest.mark.parametrize("name", [".", "sub/..", "sub/."])
def test_folder_names_that_cannot_be_renamed_are_refused_before_work(cli, files, tmp_path, command, name):
    (tmp_path / "sub").mkdir()
    before = snapshot(tmp_path)
    r = run(cli, [command, files["big"], name, "--overwrite"], tmp_path)
    expect_refused(r, f"output {name} names no new folder (give the folder by its name, not . or ..)")
    assert snapshot(tmp_path) == before


def _unshare_available():
    return _tmpfs_available()


@pytest.mark.skipif(not _unshare_available(), reason="no mount namespace permitted here")
@pytest.mark.parametrize("command", FOLDER_JOBS)
@pytest.mark.parametrize("mount", ["tmpfs", "bind"])
def test_overwrite_never_reaches_into_a_mount_inside_the_folder(cli, files, tmp_path, command, mount):
    # A tmpfs, or a bind mount of a folder of the same file system (its st_dev is the parent's),
    # inside an output folder panoproj made: refused before any work, nothing under it removed.
    _old_folder(tmp_path)
    (tmp_path / "out" / "m").mkdir()
    (tmp_path / "elsewhere").mkdir()
    (tmp_path / "elsewhere" / "theirs.txt").write_bytes(b"theirs")
    source = "-t tmpfs tmpfs" if mount == "tmpfs" else f"--bind {tmp_path / 'elsewhere'}"
    fill = f"printf theirs > {tmp_path}/out/m/theirs.txt && " if mount == "tmpfs" else ""
    script = (f"mount {source} {tmp_path}/out/m && {fill}cd {tmp_path} && "
              f"{os.path.abspath(cli)} {command} {files['png']} out --overwrite; echo \"rc=$?\"; "
              f"ls -A {tmp_path}; ls -A {tmp_path}/out/m; cat {tmp_path}/out/m/theirs.txt")
    p = subprocess.run(["unshare", "-rm", "sh", "-c", script], capture_output=True, text=True, timeout=60)
    assert "rc=1" in p.stdout, p.stdout + p.stderr
    listed = p.stdout.split("rc=1")[1].split()
    assert listed == ["elsewhere", "out", "theirs.txt", "theirs"], listed  # no temporary; the mount's file intact
    lines = [l for l in p.stderr.splitlines() if l.strip()]
    assert len(lines) == 1 and "holds a mount point, out/m" in lines[0], lines
    assert (tmp_path / "elsewhere" / "theirs.txt").read_bytes() == b"theirs"


@pytest.mark.skipif(not _unshare_available(), reason="no mount namespace permitted here")
@pytest.mark.parametrize("command", FOLDER_JOBS)
def test_an_output_folder_that_is_a_mount_point_is_refused_before_work(cli, files, tmp_path, command):
    # It cannot be renamed (EBUSY): refused at once, not after the work (which was then lost).
    _old_folder(tmp_path)
    script = (f"mount -t tmpfs tmpfs {tmp_path}/out && printf theirs > {tmp_path}/out/theirs.txt && cd {tmp_path} && "
              f"{os.path.abspath(cli)} {command} {files['big']} out --overwrite; echo \"rc=$?\"; ls -A {tmp_path}; "
              f"ls -A {tmp_path}/out")
    t0 = time.perf_counter()
    p = subprocess.run(["unshare", "-rm", "sh", "-c", script], capture_output=True, text=True, timeout=60)
    assert "rc=1" in p.stdout, p.stdout + p.stderr
    assert p.stdout.split("rc=1")[1].split() == ["out", "theirs.txt"], p.stdout
    assert "output out is a mount point, which cannot be replaced (write into a new folder inside it)" in p.stderr
    assert time.perf_counter() - t0 < 5


@pytest.mark.skipif(not _unshare_available(), reason="no mount namespace permitted here")
@pytest.mark.parametrize("command", FOLDER_JOBS)
def test_an_input_reached_through_a_bind_mount_of_the_output_is_refused(cli, files, tmp_path, command):
    # Canonical paths differ (view/in.png against out/in.png); device and inode do not.
    _old_folder(tmp_path)
    shutil.copy(files["png"], tmp_path / "out" / "in.png")
    (tmp_path / "view").mkdir()
    script = (f"mount --bind {tmp_path}/out {tmp_path}/view && cd {tmp_path} && "
              f"{os.path.abspath(cli)} {command} view/in.png out --overwrite; echo \"rc=$?\"; ls -A {tmp_path}/out")
    p = subprocess.run(["unshare", "-rm", "sh", "-c", script], capture_output=True, text=True, timeout=60)
    assert "rc=1" in p.stdout, p.stdout + p.stderr
    assert p.stdout.split("rc=1")[1].split() == ["in.png", "mine.txt", MARKER], p.stdout
    assert "input view/in.png is inside the output folder out, which the job replaces" in p.stderr, p.stderr


@pytest.mark.skipif(os.geteuid() != 0 or not shutil.which("setpriv"),
                    reason="needs root and setpriv to run the swapper as another user")
@pytest.mark.parametrize("command", FOLDER_JOBS)
def test_a_swapped_temporary_folder_never_redirects_a_write(cli, files, command):
    # Before the fix (c67a930) 10 of 10 runs wrote tiles into the root-only folder
    # (scripts/folder-race.sh); now the writes go to the folder made, by its handle.
    if not runs_as_nobody(sys.executable):
        pytest.skip(f"the swapper's interpreter ({sys.executable}) cannot start as user nobody here")
    hits, swapped = folder_race(cli, files["png"], command, runs=25, seconds=5)
    assert hits == 0 and swapped > 0, (hits, swapped)  # the swapper did act, and redirected nothing


def test_a_worker_refuses_a_staged_folder_swapped_after_begin(files, tmp_path):
    # The staged handle carries the folder's device and inode: a folder swapped in at its path is
    # refused by every task and by finish, and the one made is left to abandon.
    args = pp._job.arguments("tiles", {"image": files["png"], "out_dir": tmp_path / "out"}, {})
    staged, parts = pp._core.job_begin("tiles", args)
    assert parts > 0
    moved = staged[0] + ".moved"
    os.rename(staged[0], moved)
    os.mkdir(staged[0])
    with pytest.raises(OSError, match="is not the one the job made"):
        pp._core.job_render("tiles", args, staged, [0])
    with pytest.raises(FileNotFoundError, match="is not beside"):
        pp._core.job_finish("tiles", args, staged, [0, 0])
    assert os.listdir(staged[0]) == [] and not (tmp_path / "out").exists()
    os.rmdir(staged[0])
    os.rename(moved, staged[0])
    pp._core.job_abandon(staged)
    assert listing(tmp_path) == []


@pytest.mark.parametrize("command", FOLDER_JOBS)
def test_a_killed_runs_temporaries_are_removed_by_the_next_run(cli, tmp_path, command):
    # SIGKILL leaves the temporary folder (nothing can clean up); the next run into the same folder
    # removes it, since its process is gone, and says so. One of a live process is kept, and one
    # of the naming before (no process in the name) is left alone.
    big = tmp_path / "big.jpg"
    pp.write(str(big), smooth_equirect(4096, 2048))
    args = ["--cube-size", "4096"] if command == "tiles" else ["--size", "3000x3000"]
    p = subprocess.Popen([os.path.abspath(cli), command, str(big), "out", "--threads", "1"] + args, cwd=tmp_path,
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 20
    while time.time() < deadline and not any(n.startswith(".panoproj-") for n in os.listdir(tmp_path)):
        time.sleep(0.02)
    time.sleep(0.2)
    p.kill()
    assert p.wait() == -9
    big.unlink()
    left = [n for n in listing(tmp_path) if n.startswith(".panoproj-")]
    assert len(left) == 1, listing(tmp_path)
    space = left[0].split("-")[1]  # this boot's and pid namespace's
    with open(f"/proc/{os.getpid()}/stat") as f:
        started = f.read().rsplit(")", 1)[1].split()[19]
    live = f".panoproj-{space}-{os.getpid()}-{started}-0123456789abcdef.tmp"
    other = ".panoproj-%08x-999999999-1-0123456789abcdef.tmp" % (int(space, 16) ^ 1)  # another machine's
    for name in (live, other, ".panoproj-0123456789abcdef.tmp"):
        (tmp_path / name).mkdir()
    shutil.copy(pathlib.Path(__file__).resolve().parents[2] / "samples" / "images" / "mars_spirit_1024x512_rgba.png",
                tmp_path / "in.png")
    r = run(cli, [command, "in.png", "out2", "-q"], tmp_path)
    assert r.code == 0, r.err
    assert f"removed {left[0]}, a temporary left by a run that ended without cleaning up" in r.err, r.err
    assert listing(tmp_path) == sorted([".panoproj-0123456789abcdef.tmp", live, other, "in.png", "out2"])


@pytest.mark.parametrize("command", FOLDER_JOBS)
def test_a_full_disk_names_the_output_file_not_the_temporary(cli, files, tmp_path, command):
    _old_folder(tmp_path)
    r = run(cli, [command, files["big"], "out", "--overwrite", "--format", "png"], tmp_path, fsize=3000)
    line = expect_refused(r, "cannot write out/", "File too large")
    assert ".panoproj-" not in line, line
    _assert_old_folder(tmp_path)


@pytest.mark.parametrize("x_max", ["89.9999995", "89.99999999999", "89.99999999999999"])
def test_transverse_mercator_to_its_last_degree_is_not_black(tmp_path, x_max):
    # sin(x_max) rounded to 1 made the frame's half-width atanh(1) = inf: an all-black map.
    src = smooth_equirect(256, 128)
    tm = pp.convert(src, "equirect", f"transverse-mercator:x_max={x_max}", size=(512, 256))
    # aspect=keep: the map (about 12:1 to 23:1) fills the width, a band of the height (was: none).
    assert (tm.max(axis=2) > 0).mean() > 0.15
    back = pp.convert(tm, f"transverse-mercator:x_max={x_max}", "equirect", size=(256, 128))
    rows = slice(16, 112)  # away from the poles, where the map's pixels grow without bound
    assert np.abs(back[rows].astype(float) - src[rows]).mean() < 8


def test_tiles_take_a_partial_rgba_panorama(cli, tmp_path):
    # The bundled 210-degree RGBA fisheye (was: "channels: 5"), and an RGBA partial equirect.
    samples = pathlib.Path(__file__).resolve().parents[2] / "samples" / "images"
    for src, args in ((samples / "stellarium_trees_fisheye210_512.png", ["--from", "fisheye:fov=210", "--pitch", "-90"]),
                      (samples / "mars_spirit_1024x512_rgba.png", ["--from", "equirect:hfov=200,vfov=100"])):
        out = tmp_path / src.stem
        r = run(cli, ["tiles", src, out, "-q"] + args, tmp_path)
        assert r.code == 0, r.err
        tiles = list((out / "1").iterdir())
        assert tiles and all(pp.read(str(t)).shape[2] == 3 for t in tiles)


def _python_code(code, timeout=60, env=None):
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout,
                          env=dict(os.environ, **(env or {})))


def test_a_broadcast_array_is_counted_before_it_is_copied():
    # 65536 x 131072 x 3 of stride 0: its C-order copy (25.7 GB) was made whole, uncounted, and a
    # failed allocation crashed the interpreter. Now MemoryError before the copy.
    p = _python_code("import numpy as np, panoproj as pp\n"
                "a = np.broadcast_to(np.uint8(7), (65536, 131072, 3))\n"
                "try:\n    pp.convert(a, 'equirect', 'fisheye', size=(64, 64))\n"
                "except MemoryError as e:\n    print('MemoryError', e)\n")
    assert p.returncode == 0, p.stderr
    assert "MemoryError a C-order copy of the 131072x65536 array (it is strided or broadcast) needs 26 GB" in p.stdout, \
        p.stdout
    # One that fits is copied and converted as a contiguous one is.
    small = np.broadcast_to(np.arange(64, dtype=np.uint8)[None, :, None], (32, 64, 3))
    assert np.array_equal(pp.convert(small, "equirect", "fisheye", size=(16, 16)),
                          pp.convert(np.ascontiguousarray(small), "equirect", "fisheye", size=(16, 16)))


@pytest.mark.parametrize("call", ["tiles", "views", "convert", "convert_file_video", "convert_file_video_pyav",
                                  "stitch", "stitch_layers", "stitch_panorama", "stitch_plan", "stitch_exposure_layers",
                                  "convert_photometry", "undistort"])
def test_ctrl_c_stops_a_long_python_call_with_nothing_written(tmp_path, call):
    env = child_env(call.endswith("pyav"))
    clip = tmp_path / "clip.mkv"
    if call.startswith("convert_file_video"):
        if not FFMPEG or (call.endswith("pyav") and importlib.util.find_spec("av") is None):
            pytest.skip("ffmpeg and PyAV (test oracles) make and read the clip")
        subprocess.run([FFMPEG, "-v", "error", "-f", "lavfi", "-i", "testsrc2=size=512x256:rate=10:duration=4",
                        "-c:v", "ffv1", str(clip)], check=True)
    big = tmp_path / "big.jpg"
    pp.write(str(big), smooth_equirect(4096, 2048))
    frames = [str(big)]
    for k in range(3):  # views: several frames (distinct names)
        frames.append(str(tmp_path / f"frame{k}.jpg"))
        os.link(big, frames[-1])
    out = tmp_path / "out"
    project = tmp_path / "p.pto"  # (stitch: four equirect images onto a 12000x6000 canvas)
    if call.startswith("stitch"):
        project.write_text('p f2 w12000 h6000 v360 n"TIFF_m c:NONE r:CROP"\n' + "".join(
            f'i w4096 h2048 f4 v360 r0 p0 y{90 * k} n"big.jpg"\n' for k in range(4)))
    sparse = tmp_path / "sparse"  # (undistort: the panorama as a COLMAP model's EQUIRECTANGULAR camera)
    if call == "undistort":
        sparse.mkdir()
        (sparse / "cameras.txt").write_text("1 EQUIRECTANGULAR 4096 2048 4096 2048\n")
        (sparse / "images.txt").write_text("1 1 0 0 0 0 0 0 1 big.jpg\n\n")
    # Each 20 to 40 s uninterrupted here (lanczos3, 4x4 samples a pixel): far from done at the
    # signal on a machine several times faster.
    slow = "threads=1, interp='lanczos3', antialias=4"
    body = {"tiles": f"pp.tiles({str(big)!r}, {str(out)!r}, cube_size=4096, {slow})",
            "views": f"pp.views(frames, {str(out)!r}, size=(3000, 3000), {slow})",
            "convert": f"pp.convert(a, 'equirect', 'fisheye', size=(12000, 12000), {slow})",
            "convert_file_video": f"pp.convert_file({str(clip)!r}, {str(out) + '.mkv'!r}, dst='equirect', "
                                  f"size=(4096, 2048), codec='ffv1', {slow})",
            "undistort": f"pp.undistort({str(sparse)!r}, {str(tmp_path)!r}, {str(out)!r}, size=(3000, 3000), {slow})",
            "stitch": f"pp.stitch({str(project)!r}, {str(out)!r}, {slow})",
            "stitch_layers": f"pp.stitch_layers({str(project)!r}, {slow})",
            "stitch_panorama": f"pp.stitch_panorama({str(project)!r}, blend='multiband', {slow})",
            "stitch_plan": f"pp.StitchPlan({str(project)!r}, blend='multiband', {slow})([a] * 4)",
            "stitch_exposure_layers": f"pp.stitch({str(project)!r}, {str(out)!r}, create_exposure_layers=True, "
                                      f"{slow})",
            "convert_photometry": f"pp.convert(a, 'equirect:vignetting=1/-0.3,ev=1', 'fisheye:ev=0', "
                                  f"size=(12000, 12000), {slow})"}
    body["convert_file_video_pyav"] = body["convert_file_video"]
    body = body[call]
    code = ("import os, sys, time, numpy as np, panoproj as pp\n"
            f"a = pp.read({str(big)!r})\n"
            f"frames = {frames!r}\n"
            "print('start', flush=True)\n"
            "t0 = time.perf_counter()\n"
            f"try:\n    {body}\n    print('finished')\n"
            "except KeyboardInterrupt:\n    print('interrupted after', time.perf_counter() - t0)\n")
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=env)
    assert p.stdout.readline().strip() == "start"
    time.sleep(1.0)
    sent = time.perf_counter()
    p.send_signal(signal.SIGINT)
    out_text, err = p.communicate(timeout=60)
    assert "interrupted" in out_text, out_text + err
    assert time.perf_counter() - sent < 3, "Ctrl-C took effect late"
    made = [pathlib.Path(f).name for f in frames] + (["clip.mkv"] if clip.exists() else []) + (
        ["p.pto"] if project.exists() else []) + (["sparse"] if sparse.exists() else [])
    assert sorted(os.listdir(tmp_path)) == sorted(made)  # nothing written, no temporary


def test_a_job_over_the_address_space_limit_is_refused_at_once(cli, files, tmp_path):
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (2 << 30, resource.RLIM_INFINITY))
    t0 = time.perf_counter()
    p = subprocess.run([os.path.abspath(cli), "convert", files["jpg"], "o.png", "--to", "equirect",
                        "--size", "60000x30000"], cwd=tmp_path, capture_output=True, text=True, preexec_fn=limit)
    assert time.perf_counter() - t0 < 1
    assert p.returncode == 1 and "what the address-space limit (ulimit -v) leaves" in p.stderr, p.stderr
    assert listing(tmp_path) == []


def _child_cgroup(limit):
    """A new memory cgroup (v2, else v1) under this process's with `limit` bytes, or None."""
    for line in pathlib.Path("/proc/self/cgroup").read_text().splitlines():
        _, controllers, path = line.split(":", 2)
        if controllers == "":
            base, files = pathlib.Path("/sys/fs/cgroup" + path), ("memory.max",)
        elif "memory" in controllers.split(","):
            base, files = pathlib.Path("/sys/fs/cgroup/memory" + path), ("memory.limit_in_bytes",)
        else:
            continue
        child = base / f"panoproj-test-{os.getpid()}"
        try:
            child.mkdir()
            (child / files[0]).write_text(str(limit))
            return child
        except OSError:
            if child.exists():
                child.rmdir()
    return None


def test_a_job_over_the_cgroups_limit_is_refused_at_once(cli, files, tmp_path):
    group = _child_cgroup(500_000_000)
    if group is None:
        pytest.skip("no memory cgroup can be made here")
    try:
        t0 = time.perf_counter()
        p = subprocess.run(["sh", "-c", f"echo $$ > {group}/cgroup.procs && exec {os.path.abspath(cli)} convert "
                                        f"{files['jpg']} o.png --to equirect --size 20000x10000"],
                           cwd=tmp_path, capture_output=True, text=True)
        assert time.perf_counter() - t0 < 1
        assert p.returncode == 1 and "3/4 of what the process's cgroup still allows" in p.stderr, p.stderr
        assert listing(tmp_path) == []
    finally:
        group.rmdir()


def test_a_cgroups_file_cache_is_not_taken_for_used_memory(cli, files, tmp_path):
    # 500 MB written inside a 600 MB cgroup: its file cache, reclaimable, is charged to the cgroup.
    # A job needing about 200 MB then runs (the budget was the limit less all usage, cache included:
    # 100 MB, and the job was refused).
    group = _child_cgroup(600_000_000)
    if group is None:
        pytest.skip("no memory cgroup can be made here")
    try:
        p = subprocess.run(["sh", "-c", f"echo $$ > {group}/cgroup.procs && "
                                        "dd if=/dev/zero of=cache bs=1M count=500 status=none && "
                                        f"exec {os.path.abspath(cli)} convert {files['jpg']} o.ppm --to equirect "
                                        "--size 8000x4000 -q"],
                           cwd=tmp_path, capture_output=True, text=True, timeout=120)
        assert p.returncode == 0, p.stderr
        assert (tmp_path / "o.ppm").stat().st_size > 8000 * 4000 * 3
    finally:
        group.rmdir()


def _rle_hdr(path, width, height):
    """A Radiance HDR of run-length rows (each row one colour, a gradient down the frame): about
    1 kB a row on disk, 12 bytes a pixel decoded."""
    with open(path, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (height, width))
        runs = [127] * (width // 127) + ([width % 127] if width % 127 else [])
        for y in range(height):
            v = 0.25 + 0.5 * y / height  # mantissa in [64, 192) with exponent 128 + 0: v = m / 256
            rgbe = (int(v * 256), int(v * 128), int(v * 64), 128)
            row = bytearray(b"\x02\x02" + struct.pack(">H", width))
            for c in rgbe:
                for n in runs:
                    row += bytes((128 + n, c))
            f.write(row)


def test_a_large_rle_hdr_is_read_in_bands_at_a_small_views_scale(cli, tmp_path):
    # 16384 x 8192 (1.6 GB as floats) in 8.7 MB: a 64x64 view decodes it at 1/8 in bands of 8 rows.
    src = tmp_path / "big.hdr"
    _rle_hdr(src, 16384, 8192)
    assert src.stat().st_size < 10_000_000
    # Through a small launcher: a child forked from this process starts with its peak RSS (Linux
    # copies the high-water mark), which a worker's earlier tests may have raised past the bound.
    launcher = ("import os, subprocess, sys\n"
                "p = subprocess.Popen(sys.argv[1:], stdout=subprocess.PIPE)\n"
                "out = p.stdout.read()\n"
                "_, status, usage = os.wait4(p.pid, 0)\n"
                "print(os.waitstatus_to_exitcode(status), usage.ru_maxrss * 1024, out.decode())\n")
    p = subprocess.run([sys.executable, "-c", launcher, os.path.abspath(cli), "convert", str(src), "v.exr", "--to",
                        "equirect", "--size", "64x32", "-v"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    code, rss, out = p.stdout.split(" ", 2)
    assert code == "0", p.stdout + p.stderr
    assert "at 1/8 scale" in out, out
    assert int(rss) < 200 << 20, f"peak memory {int(rss) >> 20} MB"
    v = pp.read(str(tmp_path / "v.exr"))
    want = 0.25 + 0.5 * (np.arange(32) + 0.5) / 32  # each output row's mean source row
    assert np.abs(v[:, :, 0].mean(axis=1) - want).max() < 0.01


@pytest.mark.parametrize("call,error,needle", [
    (lambda: pp._core.job_run("video", {}), ValueError, "unknown job 'video' (expected one of: convert, maps, tiles"),
    (lambda: pp._core.job_begin("convert", {}), ValueError, "job convert has no parts"),
    (lambda: pp._core.job_run("tiles", {"tiles": 3}), ValueError, "unknown option 'tiles' (expected one of: image"),
    (lambda: pp._core.job_render("tiles", {"image": "/nonexistent.png", "out_dir": "/tmp/x"}, ("/tmp/x", 0, 0), [0]),
     FileNotFoundError, "/nonexistent.png"),
    (lambda: pp.tiles("in.png", "out", tile="512"), TypeError, "tile: '512' (expected an int"),
    (lambda: pp.views([], "out"), ValueError, "no input given"),
], ids=["unknown_job", "not_staged", "unknown_argument", "render_missing_input", "tile_text", "no_views_input"])
def test_the_job_interface_refuses_naming_the_value(call, error, needle):
    with pytest.raises(error, match=re.escape(needle)):
        call()


# ---------------------------------------------------------------------------------------------
# Videos (the convert job on a video: jobs/convert/video_convert.hpp). Clips made here by the
# ffmpeg command (a test oracle), 256x128 and 12 frames.

FFMPEG = shutil.which("ffmpeg")


@pytest.fixture(scope="module")
def clips(tmp_path_factory, cli):
    if not FFMPEG:
        pytest.skip("ffmpeg (a test oracle) is not installed")
    d = tmp_path_factory.mktemp("clips")

    def ffmpeg(*args):
        subprocess.run([FFMPEG, "-v", "error", "-y", *args], check=True, cwd=d)

    pattern = ["-f", "lavfi", "-i", "testsrc2=size=256x128:rate=24:duration=0.5"]
    ffmpeg(*pattern, "-c:v", "libx264", "-pix_fmt", "yuv420p", "ok.mp4")
    ffmpeg(*pattern, "-c:v", "libx264", "-pix_fmt", "yuv420p", "ok.mkv")
    ffmpeg("-f", "lavfi", "-i", "sine=duration=0.5", "-c:a", "aac", "audio.mp4")
    ffmpeg(*pattern, "-frames:v", "2", "-c:v", "ffv1", "-pix_fmt", "yuv422p", "ok422.mkv")
    ffmpeg(*pattern, "-frames:v", "2", "-vf", "scale=978:163", "-c:v", "ffv1", "-pix_fmt", "yuv422p",
           "cube422.mkv")  # (faces of 163 px: 81.5 chroma samples across)
    mkv = (d / "ok.mkv").read_bytes()
    mp4 = (d / "ok.mp4").read_bytes()
    at = mkv.find(b"V_MPEG4/ISO/AVC")
    (d / "unknown.mkv").write_bytes(mkv[:at] + b"V_MPEG4/ISO/XYZ" + mkv[at + 15:])
    (d / "truncated.mp4").write_bytes(mp4[:len(mp4) * 4 // 10])
    (d / "garbage.mp4").write_bytes(np.random.default_rng(5).integers(0, 256, 5000, dtype=np.uint8).tobytes())
    (d / "empty.mp4").write_bytes(b"")
    os.mkfifo(d / "fifo.mp4")
    pp.write(str(d / "f.exr"), np.zeros((32, 64, 3), np.float32))
    # Headers that lie: raw frames said to be 65535x255 (the packets hold 256x128), 2^31 - 1
    # samples in MP4's sample table, the durations of every MP4 box at 2^32 - 1 ticks.
    ffmpeg(*pattern, "-frames:v", "3", "-c:v", "rawvideo", "-pix_fmt", "yuv420p", "raw.mkv")
    raw = bytearray((d / "raw.mkv").read_bytes())
    w, h = raw.find(b"\xb0\x82\x01\x00"), raw.find(b"\xba\x81\x80")
    raw[w:w + 4], raw[h:h + 3] = b"\xb0\x82\xff\xff", b"\xba\x81\xff"
    (d / "huge_frames.mkv").write_bytes(bytes(raw))
    stsz = mp4.find(b"stsz")
    (d / "absurd_count.mp4").write_bytes(mp4[:stsz + 12] + (2**31 - 1).to_bytes(4, "big") + mp4[stsz + 16:])
    long = bytearray(mp4)
    for box, at in ((b"mvhd", 20), (b"tkhd", 24), (b"mdhd", 20)):  # (version 0: its duration's offset)
        k = long.find(box)
        long[k + at:k + at + 4] = b"\xff\xff\xff\xff"
    (d / "absurd_duration.mp4").write_bytes(bytes(long))
    # Spherical metadata panoproj cannot use (video_spherical.hpp): an equi box's bounds past the
    # frame, a cbmp padding past its cells, a right-left stereo frame (Matroska's StereoMode 11).
    def panoproj(*args):
        subprocess.run([os.path.abspath(cli), "convert", "-q", *args], check=True, cwd=d)

    panoproj("ok.mp4", "equi.mp4", "--to", "equirect", "--size", "256x128")
    panoproj("ok.mp4", "cube.mp4", "--to", "cubemap:layout=3x2,order=rludfb", "--size", "192x128")
    panoproj("ok.mp4", "sbs.mkv", "--to", "equirect:stereo=sbs", "--size", "256x64")
    equi = bytearray((d / "equi.mp4").read_bytes())
    k = equi.find(b"equi") + 8
    equi[k:k + 8] = b"\xff\xff\xff\x00\xff\xff\xff\x00"  # (top + bottom over the whole)
    (d / "bounds_past.mp4").write_bytes(bytes(equi))
    cube = bytearray((d / "cube.mp4").read_bytes())
    k = cube.find(b"cbmp") + 12
    cube[k:k + 4] = (1000).to_bytes(4, "big")
    (d / "cube_padding.mp4").write_bytes(bytes(cube))
    sbs = (d / "sbs.mkv").read_bytes()
    (d / "right_left.mkv").write_bytes(sbs.replace(b"\x53\xb8\x81\x01", b"\x53\xb8\x81\x0b", 1))
    files = {p.name: str(p) for p in d.iterdir()}
    files["missing.mp4"] = str(d / "missing.mp4")
    return files


VIDEO_CASES = [
    ("no_video_stream", "audio.mp4", "o.mp4", [], "it has no video stream"),
    ("fifo", "fifo.mp4", "o.mp4", [], "fifo.mp4"),
    ("missing", "missing.mp4", "o.mp4", [], "missing.mp4"),
    ("unknown_codec", "unknown.mkv", "o.mp4", [], "no decoder for its video codec"),
    ("truncated_header", "truncated.mp4", "o.mp4", [], "not a video libavformat can read"),
    ("garbage", "garbage.mp4", "o.mp4", [], "not a video libavformat can read"),
    ("empty", "empty.mp4", "o.mp4", [], "empty.mp4"),
    ("absurd_size", "ok.mp4", "o.mp4", ["--size", "200000x100000"], "over the memory limit"),
    ("header_says_huge_frames", "huge_frames.mkv", "o.mp4", ["--from", "pinhole:hfov=170", "--size", "512x256"],
     "huge_frames.mkv: decoding a packet"),
    ("absurd_frame_count", "absurd_count.mp4", "o.mp4", [], "not a video libavformat can read"),
    ("size_the_encoder_refuses", "ok.mp4", "o.mp4", ["--size", "20000x10000"], "refuses these settings"),
    ("no_muxer", "ok.mp4", "o.xyz", [], "o.xyz is not a video container's"),
    ("image_without_n", "ok.mp4", "o.png", [], "images of a video's frames need {n} in it"),
    ("float_images_to_video", "f.exr", "o.mp4", ["--from", "equirect"], "has float samples"),
    ("container_refuses_codec", "ok.mp4", "o.webm", ["--codec", "h264"], "webm does not take h264 video"),
    ("mp4_refuses_prores", "ok.mp4", "o.mp4", ["--codec", "prores"], "mp4 does not take prores video"),
    ("stream_out_of_range", "ok.mp4", "o.mp4", ["--stream", "3"], "--stream 3 is out of range: it has 1 video stream"),
    ("stream_negative", "ok.mp4", "o.mp4", ["--stream", "-1"], "--stream -1 is out of range"),
    ("pattern_output", "ok.mp4", "o_{n}.mp4", [], "a video's output is one video file"),
    ("crf_out_of_range", "ok.mp4", "o.mp4", ["--crf", "99"], "--crf 99 is out of range"),
    ("bitrate_nan", "ok.mp4", "o.mp4", ["--bitrate", "nan"], "--bitrate nan is not a bit rate"),
    ("bitrate_text", "ok.mp4", "o.mp4", ["--bitrate", "fast"], "--bitrate fast is not a bit rate"),
    ("gop_negative", "ok.mp4", "o.mp4", ["--gop", "-5"], "--gop -5 is out of range"),
    ("preset_unknown", "ok.mp4", "o.mp4", ["--preset", "bogus"], "refuses these settings"),
    ("image_option", "ok.mp4", "o.mp4", ["--quality", "50"], "--quality, --subsampling and --depth are for images"),
    ("fill", "ok.mp4", "o.mp4", ["--fill", "1,0,0"], "video black"),
    ("reference_engine", "ok.mp4", "o.mp4", ["--engine", "reference"], "simd or scalar engine"),
    ("odd_size", "ok.mp4", "o.mp4", ["--size", "255x128"], "does not hold whole chroma samples of yuv420p"),
    ("odd_cube_faces_422_out", "ok422.mkv", "o.mkv", ["--to", "cubemap", "--size", "978x163"],
     "978x163 does not hold whole chroma samples of yuv422p (2x1 pixels each): give --size 984x164"),
    ("odd_cube_faces_422_in", "cube422.mkv", "o.mkv", ["--from", "cubemap"],
     "its chroma planes of 489x163 (yuv422p) do not hold its cubemap whole"),
    ("nan_yaw", "ok.mp4", "o.mp4", ["--yaw", "nan"], "nan"),
    ("start_not_a_time", "ok.mp4", "o.mp4", ["--start", "1:xx"], "--start 1:xx is not a time"),
    ("start_negative", "ok.mp4", "o.mp4", ["--start", "-1"], "--start -1 is not a time"),
    ("start_nan", "ok.mp4", "o.mp4", ["--start", "nan"], "--start nan is not a time"),
    ("start_past_the_end", "ok.mp4", "o.mp4", ["--start", "60"], "it has no frame from 60"),
    ("duration_zero", "ok.mp4", "o.mp4", ["--duration", "0"], "--duration 0 is empty"),
    ("duration_inf", "ok.mp4", "o.mp4", ["--duration", "inf"], "--duration inf is not a time"),
    ("fps_zero", "ok.mp4", "o.mp4", ["--fps", "0"], "--fps 0 is not a frame rate"),
    ("fps_nan", "ok.mp4", "o.mp4", ["--fps", "nan"], "--fps nan is not a frame rate"),
    ("every_zero", "ok.mp4", "o.mp4", ["--every", "0"], "--every 0 is out of range"),
    ("fps_and_every", "ok.mp4", "o.mp4", ["--fps", "2", "--every", "3"], "give one"),
    ("spherical_bounds_past_the_frame", "bounds_past.mp4", "o.mp4", [], "not a video libavformat can read"),
    ("spherical_cube_padding_past_its_cells", "cube_padding.mp4", "o.mp4", [],
     "its spherical metadata says cubemap, padding 1000, which its frames of 192x128 do not hold"),
    ("spherical_stereo_right_left", "right_left.mkv", "o.mp4", [],
     "its spherical metadata says stereo layout 'side by side (inverted)'"),
]


@pytest.mark.parametrize("case", VIDEO_CASES, ids=[c[0] for c in VIDEO_CASES])
def test_bad_video_inputs_and_parameters(cli, clips, tmp_path, case):
    _, source, out, args, needle = case
    before = snapshot(tmp_path)
    to = [] if "--to" in args else ["--to", "equirect"]
    r = run(cli, ["convert", clips[source], out, *to, *args], tmp_path)
    expect_refused(r, needle, rss=HOSTILE_RSS)
    assert snapshot(tmp_path) == before


VIDEO_VIEWS_CASES = [
    ("garbage", ["garbage.mp4"], [], "not a video libavformat can read"),
    ("no_video_stream", ["audio.mp4"], [], "it has no video stream"),
    ("fifo", ["fifo.mp4"], [], "fifo.mp4"),
    ("video_and_image", ["ok.mp4", "f.exr"], [], "is a video: give it alone"),
    ("image_and_video", ["f.exr", "ok.mp4"], ["--from", "equirect"], "is a video among images"),
    ("start_for_an_image", ["f.exr"], ["--from", "equirect", "--start", "1"], "are for a video"),
    ("past_the_end", ["ok.mp4"], ["--start", "60"], "no frame in the range given"),
    ("fps_nan", ["ok.mp4"], ["--fps", "nan"], "--fps nan is not a frame rate"),
    ("stream_out_of_range", ["ok.mp4"], ["--stream", "2"], "--stream 2 is out of range"),
    ("absurd_view", ["ok.mp4"], ["--size", "70000x70000"], "size: 70000x70000"),
]


@pytest.mark.parametrize("case", VIDEO_VIEWS_CASES, ids=[c[0] for c in VIDEO_VIEWS_CASES])
def test_bad_video_views(cli, clips, tmp_path, case):
    _, sources, args, needle = case
    before = snapshot(tmp_path)
    r = run(cli, ["views", *[clips[s] for s in sources], "out", *args], tmp_path)
    expect_refused(r, needle, rss=HOSTILE_RSS)
    assert snapshot(tmp_path) == before


@pytest.mark.parametrize("flag,value", [("--crf", "20"), ("--codec", "hevc"), ("--fps", "2"), ("-g", "5")])
def test_a_videos_options_for_an_image_are_refused(cli, tmp_path, flag, value):
    pp.write(str(tmp_path / "pano.png"), np.zeros((32, 64, 3), np.uint8))
    before = snapshot(tmp_path)
    r = run(cli, ["convert", "pano.png", "o.png", "--to", "pinhole", flag, value], tmp_path)
    expect_refused(r, f"{flag if flag != '-g' else '--gop'} is for a video: pano.png is not one")
    assert snapshot(tmp_path) == before


def test_a_videos_views_refuse_a_client(clips, tmp_path):
    class Client:  # (begin refuses before any task is submitted)
        def submit(self, *a, **k):
            raise AssertionError("submitted")

    with pytest.raises(ValueError, match="its views are made in one process"):
        pp.views(clips["ok.mp4"], str(tmp_path / "out"), client=Client())
    assert listing(tmp_path) == []


def test_a_damaged_video_converts_with_its_concealed_packets_counted(cli, clips, tmp_path):
    data = bytearray(pathlib.Path(clips["ok.mp4"]).read_bytes())
    rng = np.random.default_rng(1)
    for at in rng.integers(len(data) * 3 // 10, len(data) * 7 // 10, 40):
        data[at] ^= 0xFF
    (tmp_path / "damaged.mp4").write_bytes(bytes(data))
    r = run(cli, ["convert", "damaged.mp4", "o.mp4", "--to", "equirect"], tmp_path)
    assert r.code == 0, r.err
    assert re.search(r"damaged.mp4: \d+ corrupt packets or frames concealed", r.err), r.err
    assert (tmp_path / "o.mp4").stat().st_size > 0
    assert listing(tmp_path) == ["damaged.mp4", "o.mp4"]


def test_a_clip_that_says_it_lasts_a_century_converts_its_frames_in_bounded_time(cli, clips, tmp_path):
    r = run(cli, ["convert", clips["absurd_duration.mp4"], "o.mp4", "--to", "equirect"], tmp_path)
    assert r.code == 0, r.err
    assert ": 12 frames in" in r.out, r.out
    assert listing(tmp_path) == ["o.mp4"]


def test_a_video_output_is_not_overwritten_without_overwrite(cli, clips, tmp_path):
    _old_files(tmp_path, ["o.mp4"])
    expect_refused(run(cli, ["convert", clips["ok.mp4"], "o.mp4", "--to", "equirect"], tmp_path),
                   "o.mp4 exists")
    _assert_old_intact(tmp_path, ["o.mp4"])


@pytest.mark.skipif(not STRACE, reason="strace (a test oracle) is not installed")
@pytest.mark.parametrize("fault", ["write-ENOSPC", "write-EIO", "fsync-EIO"])
def test_video_write_faults_leave_the_old_file(cli, clips, tmp_path, fault):
    call, err = fault.split("-")
    _old_files(tmp_path, ["o.mp4"])
    # The first write of the process is the muxer's header into the temporary; the fsync its seal.
    r = run(cli, ["convert", clips["ok.mp4"], "o.mp4", "--to", "equirect", "--overwrite"], tmp_path,
            strace=["-e", f"trace={call}", "-e", f"inject={call}:error={err}:when=1"])
    assert "(INJECTED)" in r.trace, r.trace[-2000:]
    expect_refused(r, "cannot write o.mp4", os.strerror(getattr(__import__("errno"), err)))
    _assert_old_intact(tmp_path, ["o.mp4"])


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["INT", "TERM"])
def test_signals_during_a_video_leave_nothing_behind(cli, clips, tmp_path, sig):
    if not STRACE:
        pytest.skip("strace (a test oracle) is not installed")
    _old_files(tmp_path, ["o.mp4"])
    # Each write of the temporary held 0.1 s: the signal comes while the clip is being written.
    r = run(cli, ["convert", clips["ok.mp4"], "o.mp4", "--to", "equirect", "--overwrite"], tmp_path,
            strace=["-e", "trace=write", "-e", "inject=write:delay_enter=100000"],
            on_start=_signal_once_a_temporary_exists(tmp_path, sig, 0.3))
    assert r.code in (-sig, 128 + sig), (r.code, r.err)
    _assert_old_intact(tmp_path, ["o.mp4"])


# The same cases from Python, through the plugin and through PyAV (the plugin made unloadable: the
# wheel without the system's FFmpeg libraries), each in one child whose peak memory is bounded as
# the command's: the same exception classes, one line each naming the value in Python's words,
# nothing left behind.
PYTHON_NEEDLES = {
    "crf_out_of_range": "crf=99 is out of range", "bitrate_nan": "bitrate='nan' is not a bit rate",
    "bitrate_text": "bitrate='fast' is not a bit rate", "gop_negative": "gop=-5 is out of range",
    "stream_negative": "stream=-1 is out of range", "every_zero": "every=0 is out of range",
    "odd_cube_faces_422_out": "978x163 does not hold whole chroma samples of yuv422p (2x1 pixels each): give size=984x164",
    "start_not_a_time": "start='1:xx' is not a time", "start_negative": "start='-1' is not a time",
    "start_nan": "start='nan' is not a time", "duration_zero": "duration='0' is empty",
    "duration_inf": "duration='inf' is not a time", "fps_zero": "fps='0' is not a frame rate",
    "fps_nan": "fps='nan' is not a frame rate", "fps_and_every": "fps= and every= both pick frames: give one",
    "nan_yaw": "yaw: nan",
}
PYAV_NEEDLES = {
    "unknown_codec": "no decoder for its video codec in PyAV's FFmpeg",
}
_PYTHON_VIDEO_CASES = """
import json, os, pathlib, sys, warnings
import panoproj as pp
warnings.simplefilter("ignore")
out = {}
for name, source, output, kw in json.loads(sys.argv[1]):
    d = pathlib.Path(name)
    d.mkdir()
    try:
        pp.convert_file(source, d / output, **{"dst": "equirect", **kw})
        out[name] = ["no error", "", os.listdir(d)]
    except Exception as e:
        out[name] = [type(e).__name__, str(e), os.listdir(d)]
print(json.dumps(out))
# (the peak of this process since its exec: VmHWM, which a parent's does not raise as ru_maxrss's may)
print(json.dumps([int(l.split()[1]) for l in open("/proc/self/status") if l.startswith("VmHWM")][0]))
"""


def _python_kwargs(args):
    """The command's flags of a case as convert_file's keywords."""
    out = {}
    for flag, value in zip(args[::2], args[1::2]):
        name = flag.lstrip("-").replace("-", "_")
        name = {"from": "src", "to": "dst", "g": "gop"}.get(name, name)
        if name in ("stream", "crf", "gop", "every", "quality"):
            value = int(value)
        elif name == "yaw":
            value = float(value)
        elif name == "fill":
            value = tuple(float(v) for v in value.split(","))
        out[name] = value
    return out


def _python_video_cases(clips, folder, pyav):
    cases = [(c[0], clips[c[1]], c[2], _python_kwargs(c[3])) for c in VIDEO_CASES]
    folder.mkdir()
    p = subprocess.run([sys.executable, "-c", _PYTHON_VIDEO_CASES, json.dumps(cases)], cwd=folder, env=child_env(pyav),
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.strip().splitlines()
    peak_kb = json.loads(lines[-1])
    assert peak_kb << 10 < HOSTILE_RSS, f"peak memory {peak_kb >> 10} MB"
    return json.loads(lines[-2])


_PYTHON_VIDEO_LINKS = """
import json, os, sys, warnings
import panoproj as pp
warnings.simplefilter("ignore")
clip, out = sys.argv[1], {}
open("target", "w").write("old")
for name, overwrite in (("link", False), ("dangling", False), ("link_overwritten", True)):
    os.symlink("target" if name != "dangling" else "nowhere", name + ".mkv")
    try:
        pp.convert_file(clip, name + ".mkv", dst="equirect", codec="ffv1", overwrite=overwrite)
        out[name] = ["no error", os.path.islink(name + ".mkv")]
    except Exception as e:
        out[name] = [type(e).__name__, str(e)]
out["target"] = open("target").read()
out["left"] = sorted(os.listdir("."))
print(json.dumps(out))
"""


@pytest.mark.parametrize("pyav", [False, True], ids=["plugin", "pyav"])
def test_a_python_video_output_that_is_a_link(clips, tmp_path, pyav):
    if pyav:
        pytest.importorskip("av")
    p = subprocess.run([sys.executable, "-c", _PYTHON_VIDEO_LINKS, clips["ok.mp4"]], cwd=tmp_path, env=child_env(pyav),
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    got = json.loads(p.stdout.strip().splitlines()[-1])
    for name in ("link", "dangling"):
        assert got[name][0] == "FileExistsError" and f"{name}.mkv" in got[name][1], got
    assert got["link_overwritten"] == ["no error", False], got  # (the link replaced, not its target)
    assert got["target"] == "old"
    assert got["left"] == ["dangling.mkv", "link.mkv", "link_overwritten.mkv", "target"], got


def test_bad_video_inputs_and_parameters_from_python_through_the_plugin_and_pyav(clips, tmp_path):
    pytest.importorskip("av")
    plugin = _python_video_cases(clips, tmp_path / "plugin", pyav=False)
    pyav = _python_video_cases(clips, tmp_path / "pyav", pyav=True)
    for name, _, _, _, needle in VIDEO_CASES:
        needle = PYTHON_NEEDLES.get(name, needle)
        for via, got in (("plugin", plugin[name]), ("pyav", pyav[name])):
            kind, message, left = got
            want = PYAV_NEEDLES.get(name, needle.replace("libavformat", "PyAV")) if via == "pyav" else needle
            assert want in message and "\n" not in message, (name, via, message)
            assert left == [], (name, via, left)
        assert pyav[name][0] == plugin[name][0] and plugin[name][0] in (
            "OSError", "ValueError", "MemoryError", "FileNotFoundError"), (name, plugin[name], pyav[name])


# ---------------------------------------------------------------------------------------------
# Hugin projects (stitch): each bad project, image or parameter refused in one line naming its
# line and token (or file), exit 1, nothing written, bounded time and memory; full disks and
# signals leave no layer.

STITCH_IMAGE = 'i w64 h48 f0 v50 r0 p0 y0 n"a.png"\n'
STITCH_PANO = 'p f2 w256 h128 v360 n"TIFF_m c:NONE r:CROP"\nm i5\n'
STITCH = [
    ("unknown_line", STITCH_PANO + "z f0\n" + STITCH_IMAGE, [], "t.pto:3: line: unknown line 'z f0'", False),
    ("unknown_token", STITCH_PANO + 'i w64 h48 f0 v50 Q7 n"a.png"\n', [], "t.pto:3: i line: unknown token 'Q7'", False),
    ("nan", STITCH_PANO + 'i w64 h48 f0 vnan n"a.png"\n', [], "token vnan: expected a finite number", False),
    ("inf_yaw", STITCH_PANO + 'i w64 h48 f0 v50 yinf n"a.png"\n', [], "token yinf: expected a finite number", False),
    ("huge_number", STITCH_PANO + 'i w64 h48 f0 v50 a1e400 n"a.png"\n', [], "token a1e400: expected a finite", False),
    ("fov_out_of_range", STITCH_PANO + 'i w64 h48 f0 v400 n"a.png"\n', [], "token v: expected a field of view", False),
    ("rectilinear_too_wide", STITCH_PANO + 'i w64 h48 f0 v190 n"a.png"\n', [], "hfov=190 is too wide for lens=rectilinear",
     False),
    ("lens_type", STITCH_PANO + 'i w64 h48 f7 v50 n"a.png"\n', [], "token f7: this lens type is not supported", False),
    ("projection", 'p f13 w256 h128 v360\n' + STITCH_IMAGE, [], "token f13: this panorama projection is not supported",
     False),
    ("panini_f12", 'p f12 w256 h128 v200\n' + STITCH_IMAGE, [], "libpano13's Panini (f12)", True),
    ("translation", STITCH_PANO + 'i w64 h48 f0 v50 TrX1 n"a.png"\n', [], "translation (mosaic mode) is not supported",
     False),
    ("missing_image", STITCH_PANO + 'i w64 h48 f0 v50 n"gone.png"\n', [], "gone.png", False),
    ("image_is_garbage", STITCH_PANO + 'i w64 h48 f0 v50 n"garbage.png"\n', [], "garbage.png", False),
    ("image_is_a_fifo", STITCH_PANO + 'i w64 h48 f0 v50 n"fifo.png"\n', [], "a FIFO", True),
    ("other_aspect", STITCH_PANO + 'i w64 h64 f0 v50 n"a.png"\n', [],
     "a.png: 64x48 where the project (line 3) says 64x64: another aspect cannot be scaled to it", False),
    ("mask_two_points", STITCH_PANO + STITCH_IMAGE + 'k i0 t0 p"1 1 5 5"\n', [], "a mask needs at least 3 points", False),
    ("mask_no_image", STITCH_PANO + STITCH_IMAGE + 'k i3 t0 p"1 1 5 5 9 1"\n', [], "token i3: no such image", False),
    ("crop_outside", STITCH_PANO + 'i w64 h48 f0 v50 S0,80,0,48 n"a.png"\n', [], "inside the 64x48 frame", False),
    ("link_cycle", STITCH_PANO + 'i w64 h48 f0 v=1 n"a.png"\ni w64 h48 f0 v=0 n"a.png"\n', [], "the links form a cycle",
     True),
    ("no_images", STITCH_PANO, [], "t.pto: no i lines", False),
    ("binary_project", "\x00\x01\x02p f2\n", [], "a NUL byte", False),
    ("canvas_over_budget", 'p f2 w4000000 h2000000 v360\n' + STITCH_IMAGE, ["--memory-limit", "256M"],
     "over the memory limit of 256 MB", True),
    ("image_out_of_range", STITCH_PANO + STITCH_IMAGE, ["--image", "5"], "image: 5 (the project has images 0 to 0)",
     False),
    ("images_count", STITCH_PANO + STITCH_IMAGE, ["--images", "a.png", "a.png"], "images: 2 files for a project of 1",
     False),
    ("depth", STITCH_PANO + STITCH_IMAGE, ["--depth", "half"], "depth", False),
    ("interp", STITCH_PANO + STITCH_IMAGE, ["--interp", "sinc"], "sinc", False),
    # Photometry (nona's): responses that are not, vignetting that reaches 0, absurd exposures.
    ("response_not_monotonic", STITCH_PANO + 'i w64 h48 f0 v50 Ra-9 n"a.png"\n', [], "not monotonic", False),
    ("response_huge", STITCH_PANO + 'i w64 h48 f0 v50 Rb1e300 n"a.png"\n', [], "must be a finite number", False),
    ("response_nan", STITCH_PANO + 'i w64 h48 f0 v50 Rcnan n"a.png"\n', [], "token Rcnan: expected a finite number",
     False),
    ("response_type", STITCH_PANO + 'i w64 h48 f0 v50 Rt3 n"a.png"\n', [], "token Rt3: expected 0 (EMoR) or 1", False),
    ("vignetting_reaches_zero", STITCH_PANO + 'i w64 h48 f0 v50 Va1 Vb-1.2 Vm5 n"a.png"\n', [],
     "inside the image: nothing can be divided by it", False),
    ("vignetting_negative", STITCH_PANO + 'i w64 h48 f0 v50 Va-1 Vm5 n"a.png"\n', [], "falls to -1", False),
    ("vignetting_centre_far", STITCH_PANO + 'i w64 h48 f0 v50 Va1 Vb0.1 Vx1e9 Vm5 n"a.png"\n', [],
     "vignetting centre shift", False),
    ("white_balance_zero", STITCH_PANO + 'i w64 h48 f0 v50 Er0 n"a.png"\n', [], "white balance Er0", False),
    ("white_balance_negative", STITCH_PANO + 'i w64 h48 f0 v50 Eb-2 n"a.png"\n', [], "white balance Eb-2", False),
    ("exposure_apart", STITCH_PANO + 'i w64 h48 f0 v50 Eev1e5 n"a.png"\n', [], "expected finite EVs at most 64 apart",
     False),
    ("output_mode", 'p f2 w256 h128 v360 R2\n' + STITCH_IMAGE, [], "token R2: expected a whole number in [0, 1]", False),
    ("exposure_option_nan", STITCH_PANO + STITCH_IMAGE, ["--exposure", "nan"], "exposure: nan", False),
    ("exposure_option_huge", STITCH_PANO + STITCH_IMAGE, ["--exposure", "1e9"], "exposure: ", False),
    ("exposure_and_ignore", STITCH_PANO + STITCH_IMAGE, ["--exposure", "1", "--ignore-exposure"],
     "exposure and ignore_exposure: give one", False),
    ("output_mode_option", STITCH_PANO + STITCH_IMAGE, ["--output-mode", "log"], "log", False),
    ("exposure_layers_and_exposure", STITCH_PANO + STITCH_IMAGE, ["--create-exposure-layers", "--exposure", "1"],
     "create_exposure_layers and exposure: each exposure layer is blended at its group's own", False),
    ("exposure_layers_and_ignore", STITCH_PANO + STITCH_IMAGE, ["--create-exposure-layers", "--ignore-exposure"],
     "create_exposure_layers and ignore_exposure", False),
    ("exposure_layers_hdr", STITCH_PANO + STITCH_IMAGE, ["--create-exposure-layers", "--output-mode", "hdr"],
     "create_exposure_layers: the layers are LDR", False),
    ("exposure_layers_hdr_project", 'p f2 w256 h128 v360 R1\n' + STITCH_IMAGE, ["--create-exposure-layers"],
     "the project's p line says R1: give output_mode ldr", False),
]


# The blended panorama (stitch project.pto pano.jpg): its options refused in one line, nothing
# written; "l_" rows: blend options given for layers.
STITCH_PANORAMA = [
    ("blend_unknown", "pano.jpg", ["--blend", "average"], "blend: average (expected feather or multiband)", False),
    ("levels_zero", "pano.jpg", ["--blend", "multiband", "--levels", "0"], "levels: 0 (expected 1 to 12)", False),
    ("levels_huge", "pano.jpg", ["--blend", "multiband", "--levels", "13"], "levels: 13 (expected 1 to 12)", False),
    ("levels_without_multiband", "pano.jpg", ["--levels", "4"], "levels: multiband's", False),
    ("feather_nan", "pano.jpg", ["--feather", "nan"], "feather", False),
    ("feather_negative", "pano.jpg", ["--feather", "-1"], "feather: -1", False),
    ("feather_too_wide", "pano.jpg", ["--feather", "400"], "feather: 400", False),
    ("feather_with_multiband", "pano.jpg", ["--blend", "multiband", "--feather", "5"],
     "feather: the feather's width; multiband blends by its levels", False),
    ("blend_for_layers", "l_", ["--blend", "multiband"], "is a layers' prefix (give a file such as pano.jpg", False),
    ("extent_for_panorama", "pano.jpg", ["--extent", "canvas"], "extent: shapes layers", False),
    ("compression_for_panorama", "pano.png", ["--compression", "none"], "compression: shapes layers and TIFF", False),
    ("quality_zero", "pano.jpg", ["--quality", "0"], "quality: 0 (expected 1 to 100)", False),
    ("subsampling", "pano.jpg", ["--subsampling", "411"], "411", False),
    ("over_budget", "pano.jpg", ["--memory-limit", "1M"], "the panorama 2000x1000, its images and a band's buffers needs",
     False),
    ("unknown_extension_is_a_prefix", "pano.xyz", ["--blend", "feather"], "pano.xyz is a layers' prefix", False),
]


@pytest.mark.parametrize("case", _table(STITCH_PANORAMA))
def test_stitch_panorama_bad_options(cli, stitch_folder, case):
    name, out, args, needle, _ = case
    pano = STITCH_PANO.replace("w256 h128", "w2000 h1000") if name == "over_budget" else STITCH_PANO
    (stitch_folder / "t.pto").write_text(pano + STITCH_IMAGE)
    before = snapshot(stitch_folder)
    line = expect_refused(run(cli, ["stitch", "t.pto", out, *args], stitch_folder, timeout=30), needle)
    assert len(line) < 400
    assert snapshot(stitch_folder) == before


def test_stitch_panorama_needs_overwrite_and_a_full_disk_leaves_the_old_one(cli, stitch_folder):
    (stitch_folder / "t.pto").write_text(STITCH_PANO + STITCH_IMAGE + 'i w64 h48 f0 v50 r0 p0 y30 n"a.png"\n')
    (stitch_folder / "pano.png").write_bytes(b"old")
    expect_refused(run(cli, ["stitch", "t.pto", "pano.png"], stitch_folder), "pano.png", "exists")
    r = run(cli, ["stitch", "t.pto", "pano.png", "--overwrite"], stitch_folder, fsize=3000)
    assert r.code != 0
    assert (stitch_folder / "pano.png").read_bytes() == b"old"
    assert not [p for p in stitch_folder.iterdir() if p.name.startswith(".panoproj-")]
    assert run(cli, ["stitch", "t.pto", "pano.png", "--overwrite", "--blend", "multiband"], stitch_folder).code == 0
    assert (stitch_folder / "pano.png").read_bytes()[:4] == b"\x89PNG"


# Rigs of lenses (stitch rig.yaml pano.jpg): bad rigs and options refused in one line, nothing
# written. a.png is 64x48.
RIG_LENS = "  - {spec: 'fisheye:fov=200', input: a.png, rect: 32x48+0+0}\n"
RIG_BACK = "  - {spec: 'fisheye:fov=200', input: a.png, rect: 32x48+32+0, yaw: 180}\n"
STITCH_RIG = [
    ("rig_no_lens", "lenses:\n", [], "no lenses (expected a list", False),
    ("rig_empty_json", "[]", [], "no lenses", False),
    ("rig_no_input", "- {spec: 'fisheye:fov=200'}\n", [], "lens 1 has no input", False),
    ("rig_no_spec", "- {input: a.png}\n", [], "lens 1 has no spec", False),
    ("rig_unknown_key", "- {spec: equirect, input: a.png, fov: 3}\n", [], "unknown key 'fov'", False),
    ("rig_bad_spec", "- {spec: 'fisheye:fov=nan', input: a.png}\n", [], "lens 1: spec", False),
    ("rig_missing_input", "- {spec: equirect, input: nothere.png}\n", [], "nothere.png", False),
    ("rig_garbage_input", "- {spec: equirect, input: garbage.png}\n", [], "garbage.png", False),
    ("rig_fifo_input", "- {spec: equirect, input: fifo.png}\n", [], "fifo.png", False),
    ("rig_rect_outside", "- {spec: equirect, input: a.png, rect: 64x48+1+0}\n", [], "reaches outside a.png", False),
    ("rig_rect_malformed", "- {spec: equirect, input: a.png, rect: 64x48}\n", [], "rect '64x48' (expected WxH+X+Y", False),
    ("rig_rect_zero", "- {spec: equirect, input: a.png, rect: 0x48+0+0}\n", [], "rect '0x48+0+0'", False),
    ("rig_rect_huge", "- {spec: equirect, input: a.png, rect: 99999999999x1+0+0}\n", [], "expected WxH+X+Y", False),
    ("rig_circle_malformed", "- {spec: equirect, input: a.png, circle: '1 2'}\n", [], "(expected CX CY R", False),
    ("rig_circle_and_crop", "- {spec: equirect, input: a.png, circle: 9 9 5, crop: 4x4+0+0}\n", [],
     "has a crop and a circle", False),
    ("rig_crop_outside", "- {spec: equirect, input: a.png, crop: 10x10+60+0}\n", [], "crop 10x10+60+0 reaches outside", False),
    ("rig_rects_overlap", RIG_LENS + "  - {spec: 'fisheye:fov=200', input: a.png, rect: 32x48+16+0}\n", [],
     "overlaps lens 1's", False),
    ("rig_lens_sees_nothing", "- {spec: 'pinhole:hfov=10', input: a.png, yaw: 90}\n", ["--to", "pinhole:hfov=20"],
     "lens 1 has no pixel on the panorama", False),
    ("rig_yaw_nan", "- {spec: equirect, input: a.png, yaw: nan}\n", [], "yaw 'nan' (expected -360 to 360", False),
    ("rig_key_twice", "- {spec: equirect, input: a.png, input: a.png}\n", [], "'input' given twice", False),
    ("rig_tab", "-\tspec: equirect\n", [], "a tab", False),
    ("rig_nul", "- {spec: equirect\x00}\n", [], "a NUL byte", False),
    ("rig_json_nested", '[{"spec": "equirect", "input": {"a": 1}}]', [], "not a string or number", False),
    ("rig_json_unterminated", '[{"spec": "equirect', [], "an unterminated string", False),
    ("rig_images_count", "lenses:\n" + RIG_LENS + RIG_BACK, ["--images", "a.png", "a.png"],
     "images: 2 files for a rig of 1 inputs", False),
    ("rig_image", "lenses:\n" + RIG_LENS + RIG_BACK, ["--image", "1"], "image: a Hugin project's", False),
    ("rig_second_lens_keys", "- {spec: 'dual-fisheye:ev2=1', input: a.png}\n", [], "ev2= is a second lens's", False),
    ("rig_bad_photometry", "- {spec: 'fisheye:fov=200,wb=1/0', input: a.png}\n", [],
     "lens 1: spec: white balance Eb0", False),
    ("rig_exposure_nan", "lenses:\n" + RIG_LENS + RIG_BACK, ["--exposure", "nan"], "exposure: nan", False),
    ("rig_to_photometry", "lenses:\n" + RIG_LENS + RIG_BACK, ["--to", "equirect:ev=1"],
     "photometric keys describe a lens (the panorama's exposure is --exposure", False),
    ("rig_flat_field_missing", "- {spec: equirect, input: a.png, flat_field: nothere.png}\n", [], "nothere.png", False),
    ("rig_flat_field_garbage", "- {spec: equirect, input: a.png, flat_field: garbage.png}\n", [], "garbage.png", False),
    ("rig_flat_field_size", "- {spec: equirect, input: a.png, rect: 32x48+0+0, flat_field: a.png}\n", [],
     "lens 1: spec: a flat field of 64x48 x 1 for an image of 32x48", False),
    ("rig_flat_field_zero", "- {spec: equirect, input: a.png, flat_field: black.png}\n", [],
     "the flat field's values run from 0", False),
    ("rig_exposure_layers_panorama", "lenses:\n" + RIG_LENS + RIG_BACK, ["--create-exposure-layers"],
     "create_exposure_layers: one TIFF per exposure group under a prefix; pano.jpg is a blended", False),
    ("rig_to_bad", "lenses:\n" + RIG_LENS + RIG_BACK, ["--to", "nosuch"], "nosuch", False),
    ("rig_size_bad", "lenses:\n" + RIG_LENS + RIG_BACK, ["--size", "0x10"], "size", False),
]


@pytest.mark.parametrize("case", _table(STITCH_RIG))
def test_stitch_bad_rigs(cli, stitch_folder, case):
    name, text, args, needle, _ = case
    rig = "rig.json" if text.startswith("[") else "rig.yaml"
    (stitch_folder / rig).write_text(text)
    before = snapshot(stitch_folder)
    line = expect_refused(run(cli, ["stitch", rig, "pano.jpg", *args], stitch_folder, timeout=30), needle)
    assert len(line) < 400
    assert snapshot(stitch_folder) == before


def test_stitch_size_and_to_are_a_rigs(cli, stitch_folder):
    (stitch_folder / "t.pto").write_text(STITCH_PANO + STITCH_IMAGE)
    for args in (["--size", "64x32"], ["--to", "equirect"]):
        expect_refused(run(cli, ["stitch", "t.pto", "pano.jpg", *args], stitch_folder), "a rig's panorama")
    (stitch_folder / "rig.yaml").write_text("lenses:\n" + RIG_LENS + RIG_BACK)
    assert run(cli, ["stitch", "rig.yaml", "pano.jpg", "--size", "64x32"], stitch_folder).code == 0


@pytest.fixture()
def stitch_folder(tmp_path):
    pp.write(str(tmp_path / "a.png"), smooth_equirect(64, 48))
    pp.write(str(tmp_path / "black.png"), np.zeros((48, 64), np.uint8))
    (tmp_path / "garbage.png").write_bytes(b"\x89PNG garbage" * 50)
    os.mkfifo(tmp_path / "fifo.png")
    return tmp_path


@pytest.mark.parametrize("case", _table(STITCH))
def test_stitch_bad_projects_and_parameters(cli, stitch_folder, case):
    name, text, args, needle, _ = case
    (stitch_folder / "t.pto").write_text(text)
    before = snapshot(stitch_folder)
    r = run(cli, ["stitch", "t.pto", "l_", *args], stitch_folder, timeout=30)
    line = expect_refused(r, needle)
    assert len(line) < 400
    assert snapshot(stitch_folder) == before


@pytest.mark.why
def test_stitch_a_million_image_project_is_refused_at_its_bound(cli, stitch_folder):
    (stitch_folder / "t.pto").write_text(STITCH_PANO + 'i w4 h3 f0 v50 n"a.png"\n' * 1000000)
    r = run(cli, ["stitch", "t.pto", "l_"], stitch_folder, timeout=30)
    expect_refused(r, "t.pto:65539: i line: more than 65536 images", rss=400 << 20)


@pytest.mark.parametrize("what", ["project_fifo", "project_directory", "project_missing", "project_device"])
def test_stitch_projects_that_are_not_regular_files(cli, stitch_folder, what):
    path = {"project_fifo": "fifo.png", "project_directory": ".", "project_missing": "none.pto",
            "project_device": "/dev/zero"}[what]
    r = run(cli, ["stitch", path, "l_"], stitch_folder, timeout=30)
    expect_refused(r, path)
    assert not list(stitch_folder.glob("l_*"))


def test_stitch_layers_need_overwrite_and_a_full_disk_leaves_none(cli, stitch_folder):
    (stitch_folder / "t.pto").write_text(STITCH_PANO + STITCH_IMAGE + 'i w64 h48 f0 v50 r0 p0 y90 n"a.png"\n')
    (stitch_folder / "l_0001.tif").write_bytes(b"old")
    expect_refused(run(cli, ["stitch", "t.pto", "l_"], stitch_folder), "l_0001.tif", "exists")
    # The disk fills while a layer is written (each is about 7 kB): none lands, the old file stays.
    r = run(cli, ["stitch", "t.pto", "l_", "--overwrite"], stitch_folder, fsize=3000)
    expect_refused(r, "l_000")
    assert sorted(p.name for p in stitch_folder.glob("l_*")) == ["l_0001.tif"]
    assert (stitch_folder / "l_0001.tif").read_bytes() == b"old"
    assert not [p for p in stitch_folder.iterdir() if p.name.startswith(".panoproj-")]
    assert run(cli, ["stitch", "t.pto", "l_", "--overwrite"], stitch_folder).code == 0
    assert (stitch_folder / "l_0001.tif").read_bytes()[:4] == b"II*\x00"


def test_stitch_hdr_weights_need_overwrite_and_land_with_their_layer(cli, stitch_folder):
    (stitch_folder / "t.pto").write_text(STITCH_PANO.replace("v360", "v360 R1") + STITCH_IMAGE)
    (stitch_folder / "l_0000_gray.pgm").write_bytes(b"old")
    expect_refused(run(cli, ["stitch", "t.pto", "l_"], stitch_folder), "l_0000_gray.pgm", "exists")
    assert not (stitch_folder / "l_0000.tif").exists()
    r = run(cli, ["stitch", "t.pto", "l_", "--overwrite"], stitch_folder, fsize=2000)
    assert r.code != 0
    assert (stitch_folder / "l_0000_gray.pgm").read_bytes() == b"old" and not (stitch_folder / "l_0000.tif").exists()
    assert run(cli, ["stitch", "t.pto", "l_", "--overwrite"], stitch_folder).code == 0
    assert (stitch_folder / "l_0000_gray.pgm").read_bytes()[:2] == b"P5"
    assert (stitch_folder / "l_0000.tif").read_bytes()[:4] == b"II*\x00"


def test_stitch_a_layer_that_is_a_link_is_replaced_not_its_target(cli, stitch_folder):
    (stitch_folder / "t.pto").write_text(STITCH_PANO + STITCH_IMAGE)
    target = stitch_folder / "elsewhere.tif"
    target.write_bytes(b"keep")
    os.symlink(target, stitch_folder / "l_0000.tif")
    expect_refused(run(cli, ["stitch", "t.pto", "l_"], stitch_folder), "l_0000.tif")
    assert run(cli, ["stitch", "t.pto", "l_", "--overwrite"], stitch_folder).code == 0
    assert target.read_bytes() == b"keep"
    assert not (stitch_folder / "l_0000.tif").is_symlink()


# Two exposure groups (0 and 1 EV): l_0000.tif and l_0001.tif.
EXPOSURE_PTO = STITCH_PANO + 'i w64 h48 f0 v50 Eev0 r0 p0 y0 n"a.png"\n' + 'i w64 h48 f0 v50 Eev1 r0 p0 y90 n"a.png"\n'


def test_stitch_exposure_layers_need_overwrite_a_full_disk_leaves_none_and_links_are_replaced(cli, stitch_folder):
    (stitch_folder / "t.pto").write_text(EXPOSURE_PTO)
    args = ["stitch", "t.pto", "l_", "--create-exposure-layers"]
    (stitch_folder / "l_0001.tif").write_bytes(b"old")
    expect_refused(run(cli, args, stitch_folder), "l_0001.tif", "exists")
    assert not (stitch_folder / "l_0000.tif").exists()
    # The disk fills while a layer is written (each about 40 kB, the whole canvas): none lands.
    expect_refused(run(cli, args + ["--overwrite"], stitch_folder, fsize=20000), "l_000")
    assert sorted(p.name for p in stitch_folder.glob("l_*")) == ["l_0001.tif"]
    assert (stitch_folder / "l_0001.tif").read_bytes() == b"old"
    assert not [p for p in stitch_folder.iterdir() if p.name.startswith(".panoproj-")]
    target = stitch_folder / "elsewhere.tif"
    target.write_bytes(b"keep")
    os.symlink(target, stitch_folder / "l_0000.tif")
    assert run(cli, args + ["--overwrite"], stitch_folder).code == 0
    assert target.read_bytes() == b"keep" and not (stitch_folder / "l_0000.tif").is_symlink()
    assert all((stitch_folder / f"l_000{k}.tif").read_bytes()[:4] == b"II*\x00" for k in (0, 1))


@pytest.mark.skipif(not STRACE, reason="strace (a test oracle) is not installed")
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["INT", "TERM"])
def test_stitch_exposure_layers_signals_leave_none(cli, stitch_folder, sig):
    (stitch_folder / "t.pto").write_text(EXPOSURE_PTO)
    r = run(cli, ["stitch", "t.pto", "l_", "--create-exposure-layers"], stitch_folder,
            strace=["-e", "trace=fsync", "-e", "inject=fsync:delay_enter=3000000:when=1"],
            on_start=_signal_once_a_temporary_exists(stitch_folder, sig, 0.3))
    assert r.code in (-sig, 128 + sig), (r.code, r.err)
    assert not list(stitch_folder.glob("l_*"))
    assert not [p for p in stitch_folder.iterdir() if p.name.startswith(".panoproj-")]


@pytest.mark.skipif(not STRACE, reason="strace (a test oracle) is not installed")
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["INT", "TERM"])
def test_stitch_signals_leave_no_layer(cli, stitch_folder, sig):
    (stitch_folder / "t.pto").write_text(STITCH_PANO + STITCH_IMAGE + 'i w64 h48 f0 v50 r0 p0 y90 n"a.png"\n')
    r = run(cli, ["stitch", "t.pto", "l_"], stitch_folder,
            strace=["-e", "trace=fsync", "-e", "inject=fsync:delay_enter=3000000:when=1"],
            on_start=_signal_once_a_temporary_exists(stitch_folder, sig, 0.3))
    assert r.code in (-sig, 128 + sig), (r.code, r.err)
    assert not list(stitch_folder.glob("l_*"))
    assert not [p for p in stitch_folder.iterdir() if p.name.startswith(".panoproj-")]


# ---------------------------------------------------------------------------------------------
# 10. COLMAP models (panoproj model, panoproj undistort, pp.convert_model, pp.undistort): every
# file and image checked before anything is written; one line each, nothing written.

COLMAP_CAMERAS = ("# Camera list with one line of data per camera:\n"
                  "1 OPENCV 64 48 50 51 32.5 23.5 -0.1 0.01 0.001 -0.001\n"
                  "2 OPENCV_FISHEYE 64 64 20 20 32 32 0.01 0 0 0\n")
COLMAP_IMAGES = ("# Image list with two lines of data per image:\n"
                 "1 1 0 0 0 0 0 0 1 a.png\n10 20 -1\n"
                 "2 1 0 0 0 0 0 1 2 b.png\n\n")
COLMAP_POINTS = "# 3D point list with one line of data per point:\n"


def _colmap_folder(tmp):
    """sparse/ (text), sparse_bin/ (binary), images/ a.png 64x48 and b.png 64x64."""
    sparse = tmp / "sparse"
    sparse.mkdir()
    (sparse / "cameras.txt").write_text(COLMAP_CAMERAS)
    (sparse / "images.txt").write_text(COLMAP_IMAGES)
    (sparse / "points3D.txt").write_text(COLMAP_POINTS)
    (tmp / "images").mkdir()
    pp.write(str(tmp / "images" / "a.png"), np.full((48, 64, 3), 90, np.uint8))
    pp.write(str(tmp / "images" / "b.png"), np.full((64, 64, 3), 90, np.uint8))
    pp.convert_model(str(sparse), str(tmp / "sparse_bin"), format="bin")
    os.unlink(tmp / "sparse_bin" / MARKER)


def _edit_text(name, old, new):
    def edit(tmp):
        p = tmp / "sparse" / name
        p.write_text(p.read_text().replace(old, new))
    return edit


def _edit_bytes(name, change):
    def edit(tmp):
        p = tmp / "sparse_bin" / name
        p.write_bytes(change(p.read_bytes()))
    return edit


COLMAP_CASES = [
    # (id, edit, args after the command, needle); {m}: sparse or sparse_bin
    ("model_unknown_model", _edit_text("cameras.txt", "OPENCV ", "OPENCVX "), ["undistort", "sparse"],
     "camera 1 has the model OPENCVX (expected one of COLMAP's: SIMPLE_PINHOLE"),
    ("model_param_count", _edit_text("cameras.txt", "-0.001\n", "\n"), ["undistort", "sparse"],
     "camera 1 (OPENCV) has 7 parameters (expected 8)"),
    ("model_unknown_camera", _edit_text("images.txt", "0 1 a.png", "0 7 a.png"), ["undistort", "sparse"],
     "images.txt: image 1 has the camera 7, which cameras does not list"),
    ("model_unknown_point", _edit_text("images.txt", "10 20 -1", "10 20 20"), ["undistort", "sparse"],
     "point2D 0 sees the point3D 20, which points3D does not list"),
    ("model_nan", _edit_text("cameras.txt", " 50 51", " nan 51"), ["undistort", "sparse"], "has a parameter nan"),
    ("model_id_twice", _edit_text("images.txt", "2 1 0 0 0 0 0 1 2", "1 1 0 0 0 0 0 1 2"), ["undistort", "sparse"],
     "image 1 is listed twice"),
    ("model_name_escapes", _edit_text("images.txt", " a.png", " ../a.png"), ["undistort", "sparse"],
     "the image name '../a.png' leaves the images folder"),
    ("model_zero_quaternion", _edit_text("images.txt", "1 1 0 0 0", "1 0 0 0 0"), ["undistort", "sparse"],
     "(expected finite numbers, a non-zero quaternion)"),
    ("model_huge_id", _edit_text("cameras.txt", "2 OPENCV_FISHEYE", "99999999999 OPENCV_FISHEYE"), ["model", "sparse"],
     "'99999999999' for the camera id (expected a whole number, 0 to 4294967295)"),
    ("equirect_params", _edit_text("cameras.txt", "0.01 0 0 0\n", "0.01 0 0 0\n3 EQUIRECTANGULAR 64 32 60 32\n"),
     ["undistort", "sparse"], "camera 3 (EQUIRECTANGULAR) has w, h = 60, 32 for a frame of 64x32 (expected the "
                              "panorama's size: at least the frame's)"),
    ("names_collide", lambda tmp: (_edit_text("images.txt", " a.png", " front/b.png")(tmp),
                                   os.mkdir(tmp / "images" / "front"),
                                   shutil.copy(tmp / "images" / "a.png", tmp / "images" / "front" / "b.png")),
     ["undistort", "sparse", "--max-fov", "100"], "image 2 would be written as front/b.png, another image's name"),
    ("bin_cut", _edit_bytes("images.bin", lambda b: b[:-3]), ["undistort", "sparse_bin"], "images.bin: cut short"),
    ("bin_absurd", _edit_bytes("images.bin", lambda b: (10 ** 15).to_bytes(8, "little") + b[8:]),
     ["undistort", "sparse_bin"], "says it holds 1000000000000000 images"),
    ("bin_model_id", _edit_bytes("cameras.bin", lambda b: b[:12] + (99).to_bytes(4, "little") + b[16:]),
     ["model", "sparse_bin"], "has the model id 99 (expected 0 to 17)"),
    ("bin_trailing", _edit_bytes("points3D.bin", lambda b: b + b"\0\0"), ["model", "sparse_bin"],
     "2 bytes after its points3D"),
    ("only_rigs", lambda tmp: (tmp / "sparse" / "rigs.txt").write_text("1 1 CAMERA 1\n"), ["undistort", "sparse"],
     "has rigs.txt but no frames.txt"),
    ("not_a_model", lambda tmp: None, ["undistort", "images"], "has no cameras.bin or cameras.txt"),
    ("missing_model", lambda tmp: None, ["undistort", "nowhere"], "no such folder"),
    ("missing_image", lambda tmp: os.unlink(tmp / "images" / "b.png"), ["undistort", "sparse"], "b.png"),
    ("image_size", lambda tmp: pp.write(str(tmp / "images" / "a.png"), np.zeros((40, 64, 3), np.uint8), overwrite=True),
     ["undistort", "sparse"], "images/a.png is 64x40, its camera 1 (OPENCV) 64x48 (expected the camera's size)"),
    ("image_not_an_image", lambda tmp: (tmp / "images" / "a.png").write_text("hello"), ["undistort", "sparse"],
     "a.png"),
    ("image_format", lambda tmp: (_edit_text("images.txt", " a.png", " a.exr")(tmp),
                                  shutil.copy(tmp / "images" / "a.png", tmp / "images" / "a.exr")),
     ["undistort", "sparse"], "image a.exr: undistorted images are written as JPEG, PNG or PNM (give --format jpg or png"),
    ("blank_pixels", lambda tmp: None, ["undistort", "sparse", "--blank-pixels", "2"], "blank_pixels: 2 (expected 0 to 1)"),
    ("max_fov", lambda tmp: None, ["undistort", "sparse", "--max-fov", "0"], "max_fov: 0 (expected 1 to 360)"),
    ("scales", lambda tmp: None, ["undistort", "sparse", "--min-scale", "3", "--max-scale", "2"], "max_scale: 2"),
    ("max_image_size", lambda tmp: None, ["undistort", "sparse", "--max-image-size", "-1"], "max_image_size: -1"),
    ("rig", lambda tmp: None, ["undistort", "sparse", "--rig", "sphere"], "rig: 'sphere'"),
    ("roi_text", lambda tmp: None, ["undistort", "sparse", "--roi", "0,0,1"],
     "roi: '0,0,1' (expected x0,y0,x1,y1: four fractions of the frame from 0 to 1)"),
    ("roi_order", lambda tmp: None, ["undistort", "sparse", "--roi", "0.5,0,0.2,1"], "(expected x0 < x1 and y0 < y1)"),
    ("roi_nan", lambda tmp: None, ["undistort", "sparse", "--roi", "nan,0,1,1"], "roi: 'nan,0,1,1'"),
    ("max_cam_point_norm", lambda tmp: None, ["undistort", "sparse", "--max-cam-point-norm", "-1"],
     "max_cam_point_norm: -1 (expected 0 to 1e+12)"),
    ("format", lambda tmp: None, ["undistort", "sparse", "--format", "webp"], "--format webp"),
    ("model_format", lambda tmp: None, ["model", "sparse", "--format", "json"], "format: json (expected txt or bin)"),
]


@pytest.mark.parametrize("case", COLMAP_CASES, ids=[c[0] for c in COLMAP_CASES])
def test_colmap_models_refused(cli, tmp_path, case):
    name, edit, args, needle = case
    _colmap_folder(tmp_path)
    if edit:
        edit(tmp_path)
    before = snapshot(tmp_path)
    command, model, *rest = args
    positional = [model, "images", "out"] if command == "undistort" else [model, "out"]
    r = run(cli, [command] + positional + rest, tmp_path, timeout=30)
    expect_refused(r, needle)
    assert snapshot(tmp_path) == before and not (tmp_path / "out").exists()


@pytest.mark.parametrize("case, kw, error", [
    ("missing_image", {}, FileNotFoundError), ("blank_pixels", dict(blank_pixels=-0.5), ValueError),
    ("rig_type", dict(rig=5), TypeError), ("exists", {}, FileExistsError),
    ("memory", dict(memory_limit="1M", size=(2000, 2000)), MemoryError),
])
def test_undistort_python_refusals(tmp_path, case, kw, error):
    _colmap_folder(tmp_path)
    if case == "missing_image":
        os.unlink(tmp_path / "images" / "a.png")
    if case == "exists":
        (tmp_path / "out").mkdir()
    with pytest.raises(error):
        pp.undistort(str(tmp_path / "sparse"), str(tmp_path / "images"), str(tmp_path / "out"), **kw)
    assert not (tmp_path / "out").exists() or case == "exists"


def test_undistort_lands_whole_and_overwrites_only_its_own(cli, tmp_path):
    _colmap_folder(tmp_path)
    r = run(cli, ["undistort", "sparse", "images", "out", "--size", "32x32"], tmp_path)
    assert r.code == 0, r.err
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["images", "masks", MARKER, "sparse"]
    again = run(cli, ["undistort", "sparse", "images", "out"], tmp_path)
    expect_refused(again, "exists")
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "notes.txt").write_text("mine")
    theirs = run(cli, ["undistort", "sparse", "images", "mine", "--overwrite"], tmp_path)
    expect_refused(theirs, "mine")
    assert run(cli, ["undistort", "sparse", "images", "out", "--overwrite"], tmp_path).code == 0


@pytest.mark.parametrize("command", ["undistort", "model"])
@pytest.mark.parametrize("cut", [0, 100])
def test_colmap_jobs_writes_cut_at_a_byte_offset(cli, tmp_path, cut, command):
    # RLIMIT_FSIZE: the first file past `cut` bytes fails (EFBIG); the old folder stays, nothing is left.
    work = tmp_path / "work"
    work.mkdir()
    _colmap_folder(work)
    _old_folder(tmp_path)
    args = [work / "sparse", work / "images"] if command == "undistort" else [work / "sparse"]
    r = run(cli, [command, *args, "out", "--overwrite"], tmp_path, fsize=cut)
    expect_refused(r, "cannot write ", "File too large")
    assert listing(tmp_path) == ["out", "work"]
    assert listing(tmp_path / "out") == ["mine.txt", MARKER]


@pytest.mark.skipif(not STRACE, reason="strace (a test oracle) is not installed")
@pytest.mark.parametrize("command", ["undistort", "model"])
def test_colmap_jobs_signals_leave_nothing_behind(cli, tmp_path, command):
    # strace holds the one syncfs for 3 s: every file is in the temporary folder then.
    work = tmp_path / "work"
    work.mkdir()
    _colmap_folder(work)
    _old_folder(tmp_path)
    args = [work / "sparse", work / "images"] if command == "undistort" else [work / "sparse"]
    r = run(cli, [command, *args, "out", "--overwrite"], tmp_path,
            strace=["-e", "trace=syncfs", "-e", "inject=syncfs:delay_enter=3000000:when=1"],
            on_start=_signal_once_a_temporary_exists(tmp_path, signal.SIGINT, 0.5))
    assert r.code in (-signal.SIGINT, 128 + signal.SIGINT), (r.code, r.err)
    assert listing(tmp_path) == ["out", "work"]
    assert listing(tmp_path / "out") == ["mine.txt", MARKER]


@pytest.mark.parametrize("command", ["undistort", "model"])
def test_colmap_jobs_never_write_through_a_link(cli, tmp_path, command):
    work = tmp_path / "work"
    work.mkdir()
    _colmap_folder(work)
    (tmp_path / "elsewhere").mkdir()
    (tmp_path / "elsewhere" / "keep.txt").write_text("keep")
    os.symlink(tmp_path / "elsewhere", tmp_path / "out")
    args = [work / "sparse", work / "images"] if command == "undistort" else [work / "sparse"]
    r = run(cli, [command, *args, "out", "--overwrite"], tmp_path)
    assert r.code == 1, r.err
    assert (tmp_path / "out").is_symlink() and listing(tmp_path / "elsewhere") == ["keep.txt"]


# Issue 55's additions: --face-size, a pattern's folders made, maps as .npy, a mono target's size.
# Each refused in one line, exit 1, nothing written or made (no folder left behind).
FIRST_HOUR_CASES = [
    ("face_size_text", ["convert", "{src}", "o.png", "--to", "cubemap", "--face-size", "abc"],
     "--face-size: abc is not a 64-bit integer"),
    ("face_size_huge", ["convert", "{src}", "o.png", "--to", "cubemap", "--face-size", "99999999999999999999"],
     "--face-size: 99999999999999999999 is not a 64-bit integer"),
    ("face_size_zero", ["convert", "{src}", "o.png", "--to", "cubemap", "--face-size", "0"],
     "--face-size 0 (expected 1 to 2147483647 pixels a side)"),
    ("face_size_negative", ["convert", "{src}", "o.png", "--to", "cubemap", "--face-size", "-8"],
     "--face-size -8 (expected 1 to "),
    ("face_size_over_memory", ["convert", "{src}", "o.png", "--to", "cubemap", "--face-size", "1000000"],
     "over the memory limit"),
    ("face_size_no_faces", ["convert", "{src}", "o.png", "--to", "fisheye", "--face-size", "64"],
     "fisheye has no faces"),
    ("pattern_through_a_file", ["convert", "{src}", "file/x/{face}.png", "--to", "cubemap:layout=files"],
     "output folder file is not a folder"),
    ("pattern_through_a_device_link", ["convert", "{src}", "null/x/{face}.png", "--to", "cubemap:layout=files"],
     "output folder null is not a folder"),
    ("pattern_job_refused_later", ["convert", "{src}", "made/{face}.png", "--to", "cubemap:layout=files",
                                   "--face-size", "1000000"], "over the memory limit"),
    ("maps_npy_exists", ["maps", "exists.npy", "--from", "equirect", "--source-size", "64x32", "--to", "pinhole"],
     "output exists.npy exists (pass --overwrite to replace it)"),
    ("maps_npy_missing_folder", ["maps", "no/m.npy", "--from", "equirect", "--source-size", "64x32", "--to",
                                 "pinhole"], "output folder no does not exist"),
    ("maps_npy_huge", ["maps", "m.npy", "--from", "equirect", "--source-size", "64x32", "--to", "pinhole",
                       "--size", "900000x900000"], "over the memory limit"),
    ("maps_png", ["maps", "m.png", "--from", "equirect", "--source-size", "64x32", "--to", "pinhole"],
     "output m.png cannot hold float maps (use .npy, .tif, .exr)"),
    ("mono_size", ["convert", "{src}", "o.png", "--to", "cubemap:face=1000000000"],
     "size: 6000000000x1000000000 (expected at most"),
]


@pytest.mark.parametrize("case", FIRST_HOUR_CASES, ids=[c[0] for c in FIRST_HOUR_CASES])
def test_first_hour_refusals(cli, files, tmp_path, case):
    _, args, needle = case
    (tmp_path / "file").write_bytes(b"")
    os.symlink("/dev/null", tmp_path / "null")
    (tmp_path / "exists.npy").write_bytes(b"old")
    before = snapshot(tmp_path)
    r = run(cli, [a.replace("{src}", str(files["png"])) for a in args], tmp_path, timeout=30)
    expect_refused(r, needle)
    assert snapshot(tmp_path) == before
