"""Video through PyAV (``pip install 'panoproj[av]'``): the demuxing, decoding, encoding and muxing
of the module's second video backend (python/src/pyav_package.cpp), used where the system's FFmpeg
libraries (the plugin) are missing, e.g. from the wheel; and the description of PyAV's pixel
formats that :class:`panoproj.VideoPlan` converts. The convert job, its checks, plans and reports
stay the library's: this moves frames and packets only.

Through PyAV, unlike the plugin: a stream's chroma siting is its codec's usual (PyAV does not give
the stream's); the spherical metadata is read by panoproj itself (io/container_spherical.hpp) and
written into MP4 only, not into Matroska or WebM; HDR10's static metadata and the start timecode
are not carried. Each is said where it applies (a warning)."""
from __future__ import annotations

import io
import math
import os
from fractions import Fraction
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

_SUBSAMPLINGS = {(0, 0): "444", (1, 0): "422", (1, 1): "420", (2, 0): "411", (2, 2): "410", (0, 1): "440"}
_SITINGS = ["unknown", "left", "center", "topleft", "top", "bottomleft", "bottom"]
_ATTACHED_PIC = 0x0400  # AV_DISPOSITION_ATTACHED_PIC
_MOST_PIXELS = 1 << 27  # a decoded frame's, as the plugin's (16384 x 8192)


def require() -> Any:
    """PyAV, or ImportError saying how to install it."""
    try:
        import av
    except ImportError as e:
        raise ImportError(f"{e} (pip install 'panoproj[av]', or the system's FFmpeg libraries)") from None
    return av


def _why(e: Exception) -> str:
    """FFmpeg's words for an error (its strerror), without PyAV's repetition of the path."""
    return str(getattr(e, "strerror", None) or e)


def version() -> str:
    av = require()
    return f"PyAV {av.__version__} (FFmpeg {getattr(av, 'ffmpeg_version_info', '?')})"


def planar(name: str) -> Optional[str]:
    """The planar format of 8 to 16 bits a sample (little-endian, a plane per component) holding
    the samples of format ``name`` as they are, or None."""
    av = require()
    f = av.VideoFormat(name, 64, 64)
    comps = f.components
    if not comps or f.has_palette or f.is_bayer or f.is_bit_stream:
        return None
    bits = max(c.bits for c in comps)
    if bits > 16 or any(c.bits != bits for c in comps):
        return None
    if len({c.plane for c in comps}) == len(comps) and not f.is_big_endian:
        return name
    alpha = any(c.is_alpha for c in comps)
    depth = 8 if bits <= 8 else min(b for b in (9, 10, 12, 14, 16) if b >= bits)
    suffix = "" if depth == 8 else f"{depth}le"
    if f.is_rgb:
        candidate = ("gbrap" if alpha else "gbrp") + suffix
    elif len(comps) - alpha == 1:
        candidate = None if alpha else "gray" + suffix
    else:
        shifts = (int(math.log2(64 // comps[1].width)), int(math.log2(64 // comps[1].height)))
        candidate = "yuv" + ("a" if alpha else "") + _SUBSAMPLINGS.get(shifts, "?") + "p" + suffix
    try:
        return av.VideoFormat(candidate).name if candidate else None
    except ValueError:
        return None


def pixels(name: str, color_range: int, colorspace: int, primaries: int, trc: int, codec: str) -> Dict[str, Any]:
    """The library's VideoPixels (by field) of planar format ``name`` and a stream's colour."""
    av = require()
    f = av.VideoFormat(name, 64, 64)
    comps = f.components
    yuv = not f.is_rgb and len(comps) >= 3
    from . import _core
    return _core.video_pixels({
        "pixel_format": name, "planes": len(comps), "rgb": bool(f.is_rgb), "alpha": any(c.is_alpha for c in comps),
        "packed": False, "bits": comps[0].bits,
        "log2_chroma_w": int(math.log2(64 // comps[1].width)) if yuv else 0,
        "log2_chroma_h": int(math.log2(64 // comps[1].height)) if yuv else 0,
        # (PyAV gives no siting: the coding's usual, io/video_plugin.hpp's apply_coding_defaults)
        "siting": 0, "siting_said": False, "full_range": int(color_range) == 2,
        "matrix": int(colorspace), "primaries": int(primaries), "transfer": int(trc),
    }, codec == "mjpeg")


def plane_views(frame: Any, dtype: Any, channels: int = 1) -> List[np.ndarray]:
    """Numpy views (no copy) of a frame's planes: (height, width[, channels]) with its rows'
    stride, C-contiguous where its rows are back to back."""
    out = []
    for p in frame.planes:
        item = np.dtype(dtype).itemsize
        shape: Tuple[int, ...] = (p.height, p.width) + ((channels,) if channels > 1 else ())
        strides: Tuple[int, ...] = (p.line_size, item * channels) + ((item,) if channels > 1 else ())
        out.append(np.ndarray(shape, dtype, buffer=p, strides=strides))
    return out


def _dtype(bits: int) -> Any:
    return np.dtype("<u2") if bits > 8 else np.dtype(np.uint8)


def _rgb_format(px: Dict[str, Any]) -> str:
    """The packed RGB(A) format of 8 or 16 bits of the library's packed planes."""
    deep = px["bits"] > 8
    return ("rgba64le" if deep else "rgba") if px["alpha"] else ("rgb48le" if deep else "rgb24")


def _sws_matrix(matrix: int, height: int) -> str:
    """swscale's coefficients of an AVColorSpace (unspecified: HD's usual, else SD's)."""
    named = {1: "ITU709", 4: "FCC", 5: "ITU601", 6: "SMPTE170M", 7: "SMPTE240M", 9: "BT2020", 10: "BT2020"}
    return named.get(matrix, "ITU709" if height >= 720 else "SMPTE170M")


class Reader:
    """A file's video stream ``stream`` (-1: the first; attached pictures skipped), its frames
    whose time is in [start, end) seconds, times then counted from start; with ``copy``, the
    other streams' packets in the range kept for a Writer; with ``rgb``, frames as packed RGB."""

    def __init__(self, path: str, stream: int, copy: bool, start: float, end: float, rgb: bool) -> None:
        av = require()
        self._av, self.path, self._copy, self._start, self._end = av, path, copy, start, end
        self.concealed = 0
        self.queue: List[Any] = []  # the copied streams' packets read so far
        try:
            try:
                self._c = av.open(path, metadata_errors="ignore")
            except TypeError:  # PyAV 19 has no metadata_errors (it decodes metadata leniently)
                self._c = av.open(path)
        except av.FFmpegError as e:
            self._fail(f"it is not a video PyAV can read ({_why(e)})")
        videos = [s for s in self._c.streams if s.type == "video" and not int(s.disposition) & _ATTACHED_PIC]
        if not videos:
            self._fail("it has no video stream")
        if stream >= len(videos):
            self._fail(f"--stream {stream} is out of range: it has {len(videos)} video stream"
                       f"{'' if len(videos) == 1 else 's'} (0 to {len(videos) - 1})")
        vs = self._vs = videos[max(stream, 0)]
        cc = vs.codec_context
        if cc is None:
            self._fail("no decoder for its video codec in PyAV's FFmpeg")
        if cc.width * cc.height > _MOST_PIXELS:
            self._fail(f"its frames of {cc.width}x{cc.height} are over {_MOST_PIXELS} px")
        vs.thread_type = "AUTO"
        self._tb = vs.time_base or Fraction(1, 90000)
        self._shift = int(round(start / self._tb)) if start > 0 else 0
        if start > 0:
            try:
                self._c.seek(self._shift, stream=vs, backward=True)
            except av.FFmpegError as e:
                self._fail(f"it cannot be read from {start} s ({_why(e)})")
        self._frames = self._decoded()
        self._last: Optional[int] = None
        self._pending = next(self._frames, None)  # the range's first frame (its format and colour)
        first = self._pending
        fmt = first.format.name if first is not None else (cc.format.name if cc.format else None)
        if fmt is None or cc.width < 1 or cc.height < 1:
            self._fail("its video stream has no frame size or pixel format")
        self._planar = planar(fmt)
        if self._planar is None:
            self._fail(f"its pixel format {fmt} has no planar form of 8 to 16 bits")
        colour = first if first is not None else cc
        px = pixels(self._planar, colour.color_range, colour.colorspace, colour.color_primaries, colour.color_trc,
                    cc.name)
        self._width, self._height = (first.width, first.height) if first is not None else (cc.width, cc.height)
        self._rgb: Optional[Dict[str, Any]] = None
        if rgb:
            deep = px["bits"] > 8
            fmt_rgb = _rgb_format({"bits": px["bits"], "alpha": px["alpha"]})
            self._rgb = {"format": fmt_rgb, "src_colorspace": _sws_matrix(px["matrix"], self._height),
                         "src_color_range": 2 if px["full_range"] else 1, "dst_color_range": 2,  # (AVColorRange)
                         "interpolation": "BICUBIC"}
            px.update(pixel_format=fmt_rgb, planes=1, packed=True, rgb=True, full_range=True, bits=16 if deep else 8)
        self._px = px
        rate = vs.average_rate
        duration = (float(vs.duration * self._tb) if vs.duration else
                    (self._c.duration / 1e6 if self._c.duration else 0.0))
        self.info = {
            "container": self._c.format.name, "codec": cc.name, "stream": vs.index,
            "width": self._width, "height": self._height, "pixels": px,
            "time_base": (self._tb.numerator, self._tb.denominator),
            "frame_rate": (rate.numerator, rate.denominator) if rate else (0, 1),
            "duration": duration, "frames": int(vs.frames or 0),
            "others": [self._other(s) for s in self._c.streams if s.index != vs.index],
        }

    def _fail(self, why: str) -> None:
        raise OSError(f"cannot read {self.path}: {why}")

    @staticmethod
    def _other(s: Any) -> Dict[str, Any]:
        cc = getattr(s, "codec_context", None)
        tag = getattr(cc, "codec_tag", "") if cc is not None else ""
        name = getattr(cc, "name", None) or getattr(getattr(s, "codec", None), "name", None) or "unknown"
        return {"index": s.index, "kind": s.type, "codec": name, "tag": tag if isinstance(tag, str) else ""}

    def stream(self, index: int) -> Any:
        return self._c.streams[index]

    def _in_range(self, packet: Any) -> bool:
        if self._start <= 0 and math.isinf(self._end):
            return True
        ts = packet.pts if packet.pts is not None else packet.dts
        if ts is None:
            return False
        t = float(ts * packet.time_base)
        return self._start <= t < self._end

    def _decoded(self) -> Any:
        """The video stream's frames in the range (its packets decoded; the copied streams'
        packets queued on the way)."""
        av, vs = self._av, self._vs
        try:
            for packet in self._c.demux(*([] if self._copy else [vs])):
                if packet.stream.index != vs.index:
                    if packet.size > 0 and self._in_range(packet):
                        if self._start > 0:
                            by = int(round(self._start / packet.time_base))
                            packet.pts = None if packet.pts is None else packet.pts - by
                            packet.dts = None if packet.dts is None else packet.dts - by
                        self.queue.append(packet)
                    continue
                try:
                    frames = packet.decode()
                except av.InvalidDataError:  # a damaged packet: counted, the next one tried
                    self.concealed += 1
                    continue
                except av.FFmpegError as e:
                    self._fail(f"decoding a packet ({_why(e)})")
                for f in frames:
                    t = self._time(f) * float(self._tb)  # (in doubles, as the plugin compares)
                    if t >= self._end:
                        return
                    if t >= self._start:
                        yield f
        except av.FFmpegError as e:
            self._fail(f"reading a packet ({_why(e)})")

    def _time(self, f: Any) -> int:
        """A frame's time in the stream's time base (where it has none, the last one's plus its duration)."""
        t = f.pts if f.pts is not None else (0 if self._last is None else self._last + max(f.duration or 1, 1))
        self._last = t
        return t

    def read(self) -> Optional[Tuple[List[np.ndarray], int]]:
        """The next frame's planes (views where their rows are back to back) and its time, or None."""
        f = self._pending if self._pending is not None else next(self._frames, None)
        self._pending = None
        if f is None:
            return None
        if f.width != self._width or f.height != self._height:
            self._fail(f"its frame size changes mid-stream ({f.width}x{f.height}), which panoproj does not follow")
        if f.is_corrupt:
            self.concealed += 1
        pts = (self._last or 0) - self._shift
        if self._rgb is not None:
            a = f.reformat(**self._rgb).to_ndarray(channel_last=True)
            return [np.ascontiguousarray(a)], pts
        if f.format.name != self._planar:
            f = f.reformat(format=self._planar, interpolation="POINT")
        return plane_views(f, _dtype(self._px["bits"])), pts


def open(path: str, stream: int, copy: bool, start: float, end: float, rgb: bool) -> Reader:  # noqa: A001
    return Reader(path, stream, copy, start, end, rgb)


def _named(f: Any, path: str) -> Any:
    """A file object PyAV's FFmpeg picks the muxer of by ``path``'s extension (as the plugin's does)."""
    f.name = path
    return f


def check_output(path: str, encoder: str) -> str:
    """"" when PyAV's FFmpeg has ``encoder`` and the muxer of ``path`` takes its codec, else why not."""
    av = require()
    try:
        codec = av.Codec(encoder, "w")
    except (av.FFmpegError, ValueError):
        return f"PyAV's FFmpeg has no encoder {encoder}"
    try:
        out = av.open(_named(io.BytesIO(), path), "w")
    except (av.FFmpegError, ValueError):
        return "no muxer of PyAV's FFmpeg takes its extension"
    if codec.canonical_name not in out.supported_codecs:
        return f"{out.format.name} does not take {codec.canonical_name} video"
    return ""


def _nearest(formats: List[str], given: str) -> str:
    """The encoder's format nearest ``given``: the same subsampling and alpha, the fewest bits
    not under its own; else its first."""
    av = require()
    g = av.VideoFormat(given, 64, 64)

    def key(name: str) -> Tuple[int, int, int]:
        f = av.VideoFormat(name, 64, 64)
        same = (len(f.components) == len(g.components) and f.is_rgb == g.is_rgb
                and [(c.width, c.height) for c in f.components] == [(c.width, c.height) for c in g.components])
        bits = f.components[0].bits
        return (0 if same else 1, 0 if bits >= g.components[0].bits else 1, bits)

    return min(formats, key=key)


class Writer:
    """An encoder and muxer into the open temporary ``fd`` of ``path`` (the library renames it),
    copying the other streams of ``reader`` where the container takes them."""

    def __init__(self, fd: int, path: str, s: Dict[str, Any], reader: Optional[Reader]) -> None:
        self._av = require()
        self.path, self.notes = path, []
        self._file = _named(io.FileIO(os.dup(fd), "r+b"), path)
        try:
            self._open(s, reader)
        except BaseException:
            self._file.close()
            raise

    def _fail(self, why: str) -> None:
        raise OSError(f"cannot write {self.path}: {why}")

    def _open(self, s: Dict[str, Any], reader: Optional[Reader]) -> None:
        av, px = self._av, s["pixels"]
        try:
            self._c = av.open(self._file, "w")
        except (av.FFmpegError, ValueError) as e:
            self._fail(f"no muxer of PyAV's FFmpeg takes its extension ({_why(e)})")
        codec = av.Codec(s["codec"], "w")
        formats = [f.name for f in (codec.video_formats or [])]
        self._w, self._h, self._px = s["width"], s["height"], px
        colour = {"color_range": 2 if px["full_range"] else 1, "colorspace": px["matrix"],
                  "color_primaries": px["primaries"], "color_trc": px["transfer"]}
        self._graph: Any = None
        if px["packed"]:
            # Packed RGB (images): made BT.709 limited-range 4:2:0 (8 or 10 bits by the samples'
            # depth), chroma sited left as H.264's, by swscale as the plugin makes it.
            want = "yuv420p10le" if px["bits"] > 8 else "yuv420p"
            self._enc = want if not formats or want in formats else _nearest(formats, want)
            yuv = not av.VideoFormat(self._enc).is_rgb
            self._graph = self._rgb_graph(yuv)
            colour = ({"color_range": 1, "colorspace": 1, "color_primaries": 1, "color_trc": 13} if yuv else
                      {"color_range": 2, "colorspace": 0, "color_primaries": 1, "color_trc": 13})
        else:
            self._enc = px["pixel_format"]
            if formats and self._enc not in formats:
                self._enc = _nearest(formats, self._enc)
                self.notes.append(f"encoder {s['codec']} takes no {px['pixel_format']}: written as {self._enc}")
        options = {}
        if px["packed"] or px["siting_said"]:  # (AVChromaLocation's names; RGB made YUV: sited left)
            options["chroma_sample_location"] = ("left" if px["packed"] else
                                                 _SITINGS[px["siting"]])
        if s["crf"] >= 0 and s["bitrate"] == 0:
            options["crf"] = str(s["crf"])
        if s["preset"]:
            options["preset"] = s["preset"]
        rate = Fraction(*s["frame_rate"]) if s["frame_rate"][0] > 0 else None
        v = self._v = self._c.add_stream(s["codec"], rate=rate, options=options)
        cc = v.codec_context
        cc.width, cc.height, cc.pix_fmt = self._w, self._h, self._enc
        cc.time_base = v.time_base = Fraction(*s["time_base"])
        for key, value in colour.items():
            setattr(cc, key, value)
        if s["gop"] > 0:
            cc.gop_size = s["gop"]
        if s["bitrate"] > 0:
            cc.bit_rate = s["bitrate"]
        cc.thread_count = s["threads"]
        self._tb = cc.time_base
        self._copied: Dict[int, Any] = {}
        self._reader = reader
        if reader is not None:
            for o in reader.info["others"]:
                self._add_copied(reader, o)
        if s["spherical"]:  # (MP4's boxes panoproj writes itself: python/src/pyav_package.cpp)
            self.notes.append(f"{self.path}: no spherical metadata written: through PyAV panoproj writes it into "
                              "MP4 only (the system's FFmpeg libraries write Matroska's and WebM's: apt install "
                              "libavformat59 libavcodec59 libswscale6)")
        try:
            cc.open()
        except (av.FFmpegError, ValueError) as e:
            given = f"{self._w}x{self._h} {self._enc}" + "".join(f", {k} {v}" for k, v in options.items())
            self._fail(f"encoder {s['codec']} refuses these settings ({_why(e)}; {given})")

    def _rgb_graph(self, yuv: bool) -> Any:
        av = self._av
        graph = av.filter.Graph()
        chain = [graph.add_buffer(width=self._w, height=self._h, format=_rgb_format(self._px), time_base=Fraction(1, 25)),
                 graph.add("scale", "flags=bicubic+full_chroma_inp:in_range=full:" + (
                     "out_range=limited:out_color_matrix=bt709:out_h_chr_pos=0:out_v_chr_pos=128" if yuv
                     else "out_range=full")),
                 graph.add("format", self._enc), graph.add("buffersink")]
        for a, b in zip(chain, chain[1:]):
            a.link_to(b)
        graph.configure()
        return graph

    def _add_copied(self, reader: Reader, o: Dict[str, Any]) -> None:
        st = reader.stream(o["index"])
        dropped = f"stream {o['index']} ({o['kind']}, {o['codec']}{', ' + o['tag'] if o['tag'] else ''}) dropped: "
        if o["kind"] not in ("audio", "subtitle", "data") or o["codec"] not in self._c.supported_codecs:
            self.notes.append(dropped + f"{self._c.format.name} does not take it")
            return
        try:
            self._copied[o["index"]] = self._c.add_stream_from_template(st)
        except (self._av.FFmpegError, ValueError, TypeError) as e:
            self.notes.append(dropped + f"PyAV cannot copy it ({_why(e)})")

    def _mux(self, packets: Any) -> None:
        try:
            for p in packets:
                self._c.mux(p)
        except self._av.FFmpegError as e:
            self._fail(f"muxing a packet ({_why(e)})")

    def _copy_queued(self) -> None:
        if self._reader is None:
            return
        queue, self._reader.queue = self._reader.queue, []
        for p in queue:
            out = self._copied.get(p.stream.index)
            if out is not None:
                p.stream = out
                self._mux([p])

    def _encode(self, frame: Any) -> None:
        try:
            packets = self._v.encode(frame)
        except self._av.FFmpegError as e:
            self._fail(f"encoding a frame ({_why(e)})")
        self._mux(packets)

    def write(self, planes: List[np.ndarray], pts: int) -> None:
        """Encodes one frame (its planes as the library gives them; pts in the time base given)."""
        av, px = self._av, self._px
        if self._graph is not None:
            rgb = av.VideoFrame.from_ndarray(np.ascontiguousarray(planes[0]), format=_rgb_format(px))
            rgb.pts = pts
            self._graph.push(rgb)
            frame = self._graph.pull()
        else:
            frame = av.VideoFrame(self._w, self._h, px["pixel_format"])
            for view, plane in zip(plane_views(frame, _dtype(px["bits"])), planes):
                view[...] = plane
            if self._enc != px["pixel_format"]:
                frame = frame.reformat(format=self._enc, interpolation="BICUBIC")
        frame.pts, frame.time_base = pts, self._tb
        self._encode(frame)
        self._copy_queued()

    def finish(self) -> None:
        """Flushes the encoder, copies the rest of the other streams, writes the trailer."""
        self._encode(None)
        self._copy_queued()
        try:
            self._c.close()
            self._file.flush()
        except (self._av.FFmpegError, OSError) as e:
            self._fail(f"writing its index ({_why(e)})")
        finally:
            self._file.close()


def create(fd: int, path: str, settings: Dict[str, Any], reader: Optional[Reader]) -> Writer:
    return Writer(fd, path, settings, reader)
