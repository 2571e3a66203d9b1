// The FFmpeg plugin (libpanoproj_video.so, video_plugin.hpp): demuxing and decoding a video
// stream into planes, encoding planes and muxing them with the source's other streams copied
// packet for packet. The only code that includes FFmpeg. Written against FFmpeg 5.1; where the
// API moved in 6.1 and 7.x the #if on the library versions says so.
extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/avutil.h>
#include <libavutil/imgutils.h>
#include <libavutil/mastering_display_metadata.h>
#include <libavutil/opt.h>
#include <libavutil/pixdesc.h>
#include <libavutil/spherical.h>
#include <libavutil/stereo3d.h>
#include <libswscale/swscale.h>
}

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <deque>
#include <mutex>

#include "io/video_plugin.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {

std::string av_error(int err) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(err, text, sizeof text);
  return text;
}

// The packets of the copied streams a reader meets, which its writer takes (on another thread).
class PacketQueue {
 public:
  // A hostile file's copied streams could hold the whole file ahead of its video; bounded.
  static constexpr int64_t kMostBytes = int64_t{1} << 30;
  void push(AVPacket* p, const std::string& path) {
    std::lock_guard<std::mutex> lock(mutex_);
    bytes_ += p->size;
    if (bytes_ > kMostBytes)
      throw Error(
          "cannot read " + path +
              ": over 1 GiB of audio or data packets ahead of its video (badly interleaved)",
          ErrorKind::File);
    packets_.push_back(p);
  }
  AVPacket* pop() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (packets_.empty()) return nullptr;
    AVPacket* p = packets_.front();
    packets_.pop_front();
    bytes_ -= p->size;
    return p;
  }
  ~PacketQueue() {
    for (AVPacket* p : packets_) av_packet_free(&p);
  }

 private:
  std::mutex mutex_;
  std::deque<AVPacket*> packets_;
  int64_t bytes_ = 0;
};

// A planar format of native-endian samples of 8 to 16 bits, one component a plane (in FFmpeg's
// order of planes: Y Cb Cr, or G B R, then alpha; what crosses to the library as is); false for
// packed, semi-planar, bitstream, float, palette, hardware.
bool crosses_as_is(const AVPixFmtDescriptor* d) {
  if (!d || !(d->flags & AV_PIX_FMT_FLAG_PLANAR) ||
      (d->flags & (AV_PIX_FMT_FLAG_BITSTREAM | AV_PIX_FMT_FLAG_FLOAT | AV_PIX_FMT_FLAG_PAL |
                   AV_PIX_FMT_FLAG_HWACCEL | AV_PIX_FMT_FLAG_BE)))
    return false;
  if (d->nb_components < 1 || d->nb_components > 4) return false;
  const int bytes = d->comp[0].depth > 8 ? 2 : 1;
  unsigned planes = 0;
  for (int c = 0; c < d->nb_components; ++c) {
    const AVComponentDescriptor& k = d->comp[c];
    if (k.plane >= d->nb_components || k.step != bytes || k.offset != 0 || k.shift != 0 ||
        k.depth != d->comp[0].depth)
      return false;
    planes |= 1u << k.plane;
  }
  return planes == (1u << d->nb_components) - 1;
}

// The planar format a decoded format crosses as: itself, else the one with its components,
// subsampling and depth (rounded up to 8, 10, 12 or 16).
AVPixelFormat planar_for(AVPixelFormat f) {
  const AVPixFmtDescriptor* d = av_pix_fmt_desc_get(f);
  if (!d) return AV_PIX_FMT_NONE;
  if (crosses_as_is(d)) return f;
  int depth = 0;
  for (int c = 0; c < d->nb_components; ++c) depth = std::max(depth, d->comp[c].depth);
  const bool rgb = d->flags & AV_PIX_FMT_FLAG_RGB, alpha = d->flags & AV_PIX_FMT_FLAG_ALPHA;
  AVPixelFormat best = AV_PIX_FMT_NONE;
  int best_depth = 99;
  for (const AVPixFmtDescriptor* q = av_pix_fmt_desc_next(nullptr); q;
       q = av_pix_fmt_desc_next(q)) {
    if (!crosses_as_is(q) || q->nb_components != d->nb_components ||
        bool(q->flags & AV_PIX_FMT_FLAG_RGB) != rgb ||
        bool(q->flags & AV_PIX_FMT_FLAG_ALPHA) != alpha || q->log2_chroma_w != d->log2_chroma_w ||
        q->log2_chroma_h != d->log2_chroma_h || q->comp[0].depth < depth ||
        q->comp[0].depth >= best_depth)
      continue;
    best = av_pix_fmt_desc_get_id(q), best_depth = q->comp[0].depth;
  }
  return best;
}

// An enum field of FFmpeg's as the int it holds: a file may put any value there (a chroma
// location of 33, found by fuzzing), and loading one outside the enum's range is undefined.
template <class E>
int held(const E& e) {
  static_assert(sizeof(E) == sizeof(int));
  int v;
  std::memcpy(&v, &e, sizeof v);
  return v;
}

VideoPixels pixels_of(AVPixelFormat planar, const AVCodecParameters& p) {
  const AVPixFmtDescriptor* d = av_pix_fmt_desc_get(planar);
  VideoPixels v;
  v.pixel_format = d->name;
  v.planes = d->nb_components;
  v.rgb = d->flags & AV_PIX_FMT_FLAG_RGB;
  v.alpha = d->flags & AV_PIX_FMT_FLAG_ALPHA;
  v.bits = d->comp[0].depth;
  v.log2_chroma_w = d->log2_chroma_w, v.log2_chroma_h = d->log2_chroma_h;
  const int siting = held(p.chroma_location);  // (one FFmpeg does not know: unspecified)
  v.siting =
      siting > 0 && siting <= 6 ? static_cast<ChromaSiting>(siting) : ChromaSiting::Unspecified;
  v.full_range = held(p.color_range) == AVCOL_RANGE_JPEG;
  apply_coding_defaults(v, p.codec_id == AV_CODEC_ID_MJPEG);
  // (Colours FFmpeg does not know: unspecified, so the encoder is given a value of its enums.)
  const auto known = [](int c, int nb) { return c >= 0 && c < nb ? c : 2; };
  v.matrix = known(held(p.color_space), AVCOL_SPC_NB);
  v.primaries = known(held(p.color_primaries), AVCOL_PRI_NB);
  v.transfer = known(held(p.color_trc), AVCOL_TRC_NB);
  return v;
}

// A scaler between two formats of one size (bicubic chroma, accurate rounding) with the chroma
// positions given in 1/256 luma pixels (-513: swscale's default); null if it cannot be made.
SwsContext* scaler(Size size, AVPixelFormat from, AVPixelFormat to, int src_h, int src_v, int dst_h,
                   int dst_v) {
  SwsContext* s = sws_alloc_context();
  if (!s) return nullptr;
  av_opt_set_int(s, "srcw", size.width, 0), av_opt_set_int(s, "srch", size.height, 0);
  av_opt_set_int(s, "dstw", size.width, 0), av_opt_set_int(s, "dsth", size.height, 0);
  av_opt_set_int(s, "src_format", from, 0), av_opt_set_int(s, "dst_format", to, 0);
  av_opt_set_int(s, "sws_flags", SWS_BICUBIC | SWS_FULL_CHR_H_INP,
                 0);  // (5.1: accurate_rnd and full_chroma_int are worse here)
  av_opt_set_int(s, "src_h_chr_pos", src_h, 0), av_opt_set_int(s, "src_v_chr_pos", src_v, 0);
  av_opt_set_int(s, "dst_h_chr_pos", dst_h, 0), av_opt_set_int(s, "dst_v_chr_pos", dst_v, 0);
  if (sws_init_context(s, nullptr, nullptr) < 0) sws_freeContext(s), s = nullptr;
  return s;
}

const char* kind_name(AVMediaType t) {
  switch (t) {
    case AVMEDIA_TYPE_AUDIO:
      return "audio";
    case AVMEDIA_TYPE_SUBTITLE:
      return "subtitle";
    case AVMEDIA_TYPE_DATA:
      return "data";
    case AVMEDIA_TYPE_ATTACHMENT:
      return "attachment";
    case AVMEDIA_TYPE_VIDEO:
      return "video";
    default:
      return "unknown";
  }
}

std::string tag_text(uint32_t tag) {
  if (!tag) return "";
  std::string s;
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>((tag >> (8 * i)) & 0xff);
    s += (c >= 32 && c < 127) ? c : '?';
  }
  return s;
}

SphericalVideo spherical_of(const AVStream* st);

class FfReader final : public VideoReader {
 public:
  // skip: a stream neither copied nor listed among the others (a pair's second strip), -1: none.
  FfReader(const std::string& path, int stream, bool copy, const VideoRange& range, bool rgb,
           int skip = -1)
      : path_(path), copy_(copy), range_(range), skip_(skip) {
    try {  // (a constructor that throws runs no destructor)
      open(stream, rgb);
    } catch (...) {
      release();
      throw;
    }
  }

  ~FfReader() override { release(); }

  void open(int stream, bool rgb) {
    const std::string& path = path_;
    int err = avformat_open_input(&fmt_, path.c_str(), nullptr, nullptr);
    if (err < 0) fail("it is not a video libavformat can read (" + av_error(err) + ")");
    find_stream_info();
    pick(stream);
    AVStream* st = fmt_->streams[info_.stream];
    const AVCodec* codec = avcodec_find_decoder(st->codecpar->codec_id);
    if (!codec)
      fail("no decoder for its video codec " +
           std::string(avcodec_get_name(st->codecpar->codec_id)) + " in these FFmpeg libraries");
    dec_ = avcodec_alloc_context3(codec);
    if (!dec_ || avcodec_parameters_to_context(dec_, st->codecpar) < 0)
      fail("its decoder cannot be set up");
    dec_->thread_count = 0;
    dec_->max_pixels = int64_t{1} << 27;  // (a frame over 16384 x 8192 refused, not allocated)
    dec_->pkt_timebase = st->time_base;
    err = avcodec_open2(dec_, codec, nullptr);
    if (err < 0)
      fail("its " + std::string(codec->name) + " decoder cannot be opened (" + av_error(err) + ")");
    packet_ = av_packet_alloc();
    frame_ = av_frame_alloc();
    if (!packet_ || !frame_) fail("out of memory");
    if (range_.start > 0) {
      // From the keyframe at or before the start (frames before it are decoded and dropped).
      const int64_t at =
          av_rescale_q(static_cast<int64_t>(std::llround(range_.start * AV_TIME_BASE)),
                       AV_TIME_BASE_Q, st->time_base);
      err = av_seek_frame(fmt_, info_.stream, at, AVSEEK_FLAG_BACKWARD);
      if (err < 0)
        fail("it cannot be read from " + std::to_string(range_.start) + " s (" + av_error(err) +
             ")");
    }
    // The size, pixel format and colour as the decoder finds them in the range's first frame
    // (kept for read()): what find_stream_info() left to it.
    prime();
    if (dec_->pix_fmt != AV_PIX_FMT_NONE && avcodec_parameters_from_context(st->codecpar, dec_) < 0)
      fail("out of memory");
    if (st->codecpar->width < 1 || st->codecpar->height < 1 || st->codecpar->format < 0)
      fail("its video stream has no frame size or pixel format");
    planar_ = planar_for(static_cast<AVPixelFormat>(st->codecpar->format));
    if (planar_ == AV_PIX_FMT_NONE)
      fail("its pixel format " +
           std::string(av_get_pix_fmt_name(static_cast<AVPixelFormat>(st->codecpar->format))) +
           " has no planar form of 8 to 16 bits");
    info_.container = fmt_->iformat->name;
    info_.codec = codec->name;
    info_.size = {st->codecpar->width, st->codecpar->height};
    info_.pixels = pixels_of(planar_, *st->codecpar);
    from_full_range_ = info_.pixels.full_range;
    if (rgb) to_rgb();
    info_.time_base[0] = st->time_base.num, info_.time_base[1] = st->time_base.den;
    info_.frame_rate[0] = st->avg_frame_rate.num, info_.frame_rate[1] = st->avg_frame_rate.den;
    if (st->duration > 0)
      info_.duration = static_cast<double>(st->duration) * av_q2d(st->time_base);
    else if (fmt_->duration > 0)
      info_.duration = static_cast<double>(fmt_->duration) / AV_TIME_BASE;
    info_.frames = st->nb_frames;
    info_.spherical = spherical_of(st);
    for (unsigned i = 0; i < fmt_->nb_streams; ++i) {
      if (static_cast<int>(i) == info_.stream || static_cast<int>(i) == skip_) continue;
      const AVCodecParameters* p = fmt_->streams[i]->codecpar;
      info_.others.push_back({static_cast<int>(i), kind_name(p->codec_type),
                              avcodec_get_name(p->codec_id), tag_text(p->codec_tag)});
    }
  }

  // The streams' parameters the header leaves out, found by reading packets; a video's without
  // decoding a frame (which the single-threaded probe would, then the decoder again: 0.15 s for a
  // 4K H.264 keyframe), prime() reads them from the first frame instead.
  void find_stream_info() {
    std::vector<AVDictionary*> options(fmt_->nb_streams, nullptr);
    for (unsigned i = 0; i < fmt_->nb_streams; ++i)
      if (fmt_->streams[i]->codecpar->codec_type == AVMEDIA_TYPE_VIDEO)
        av_dict_set(&options[i], "skip_frame", "all", 0);
    const int err = avformat_find_stream_info(fmt_, options.data());
    for (AVDictionary*& d : options) av_dict_free(&d);
    if (err < 0) fail("its streams cannot be read (" + av_error(err) + ")");
  }

  void release() {
    av_frame_free(&pending_);
    av_frame_free(&frame_);
    av_packet_free(&packet_);
    avcodec_free_context(&dec_);
    avformat_close_input(&fmt_);
    sws_freeContext(sws_);
    sws_ = nullptr;
  }

  const VideoInfo& info() const override { return info_; }
  int64_t concealed() const override { return concealed_; }

  bool read(VideoFrame& out) override {
    if (pending_) {  // (decoded ahead: prime)
      av_frame_move_ref(frame_, pending_);
      av_frame_free(&pending_);
    } else if (!next_frame()) {
      return false;
    }
    take(out);
    av_frame_unref(frame_);
    return true;
  }

  // The range's first frame's side data of `type` (HDR10's, which HEVC carries in its frames);
  // "" if none.
  std::string first_frame_side_data(AVFrameSideDataType type) {
    const AVFrameSideData* sd = pending_ ? av_frame_get_side_data(pending_, type) : nullptr;
    return sd ? std::string(reinterpret_cast<const char*>(sd->data), sd->size) : std::string();
  }

  // The copied streams' packets read so far (AVFormatContext's streams name their parameters).
  PacketQueue& queue() { return queue_; }
  const AVFormatContext* format() const { return fmt_; }
  bool copying() const { return copy_; }

 private:
  // The range's first frame decoded ahead into pending_ (none if the range has none).
  void prime() {
    if (!next_frame()) return;
    pending_ = av_frame_alloc();
    if (!pending_) fail("out of memory");
    av_frame_move_ref(pending_, frame_);
  }

  // The next frame in the range into frame_; false at the end.
  bool next_frame() {
    for (;;) {
      const int got = avcodec_receive_frame(dec_, frame_);
      if (got == 0) {
        // (In the stream's time base: a frame is in the range by its own time.)
        const double t =
            static_cast<double>(frame_time()) * av_q2d(fmt_->streams[info_.stream]->time_base);
        if (t >= range_.end) {
          av_frame_unref(frame_);
          return false;
        }
        if (t < range_.start) {
          av_frame_unref(frame_);
          continue;
        }
        return true;
      }
      if (got == AVERROR_EOF) return false;
      if (got != AVERROR(EAGAIN)) {
        if (got == AVERROR_INVALIDDATA) {  // a damaged frame: counted, the next one tried
          ++concealed_;
          continue;
        }
        fail("decoding a frame (" + av_error(got) + ")");
      }
      feed();
    }
  }

  [[noreturn]] void fail(const std::string& why) const {
    throw Error("cannot read " + path_ + ": " + why, ErrorKind::File);
  }

  void pick(int wanted) {
    int seen = 0;
    for (unsigned i = 0; i < fmt_->nb_streams; ++i) {
      const AVStream* st = fmt_->streams[i];
      if (st->codecpar->codec_type != AVMEDIA_TYPE_VIDEO ||
          (st->disposition & AV_DISPOSITION_ATTACHED_PIC))
        continue;
      if (wanted < 0 || seen == wanted) {
        info_.stream = static_cast<int>(i);
        return;
      }
      ++seen;
    }
    if (seen == 0 && wanted < 0) fail("it has no video stream");
    fail("--stream " + std::to_string(wanted) + " is out of range: it has " + std::to_string(seen) +
         " video stream" + (seen == 1 ? "" : "s") + " (0 to " + std::to_string(seen - 1) + ")");
  }

  // Sends the next packet of the video stream to the decoder (queues the copied streams'
  // packets met on the way); at the end of the file, the flush.
  void feed() {
    if (at_end_) fail("the decoder wants more after the end");
    for (;;) {
      const int err = av_read_frame(fmt_, packet_);
      if (err == AVERROR_EOF || (err < 0 && avio_feof(fmt_->pb))) {
        at_end_ = true;
        avcodec_send_packet(dec_, nullptr);
        return;
      }
      if (err < 0) fail("reading a packet (" + av_error(err) + ")");
      if (packet_->stream_index == info_.stream) {
        const int sent = avcodec_send_packet(dec_, packet_);
        av_packet_unref(packet_);
        if (sent == AVERROR_INVALIDDATA) {
          ++concealed_;
          continue;
        }
        if (sent < 0 && sent != AVERROR(EAGAIN)) fail("decoding a packet (" + av_error(sent) + ")");
        return;
      }
      if (copy_ && packet_->stream_index != skip_ && in_range(*packet_)) {
        AVPacket* kept = av_packet_clone(packet_);
        if (!kept) fail("out of memory");
        shift(*kept, fmt_->streams[kept->stream_index]->time_base);
        queue_.push(kept, path_);
      }
      av_packet_unref(packet_);
    }
  }

  // Frames as packed RGB(A) from here on.
  void to_rgb() {
    VideoPixels& v = info_.pixels;
    const bool deep = v.bits > 8;
    planar_ = v.alpha ? (deep ? AV_PIX_FMT_RGBA64LE : AV_PIX_FMT_RGBA)
                      : (deep ? AV_PIX_FMT_RGB48LE : AV_PIX_FMT_RGB24);
    yuv_ = !v.rgb && v.planes >= 3;
    matrix_ = info_.pixels.matrix;
    if (matrix_ == AVCOL_SPC_UNSPECIFIED || matrix_ == AVCOL_SPC_RGB)  // (HD's usual, else SD's)
      matrix_ = info_.size.height >= 720 ? AVCOL_SPC_BT709 : AVCOL_SPC_SMPTE170M;
    v.pixel_format = av_get_pix_fmt_name(planar_);
    v.planes = 1, v.packed = true, v.rgb = true, v.full_range = true;
    v.bits = deep ? 16 : 8;
  }

  // The scaler to RGB: the stream's matrix and range, its chroma siting (in 1/256 luma pixels).
  SwsContext* rgb_scaler(AVPixelFormat from) {
    const VideoPixels& v = info_.pixels;
    const bool left = v.siting == ChromaSiting::Left || v.siting == ChromaSiting::TopLeft ||
                      v.siting == ChromaSiting::BottomLeft;
    const int vpos = v.siting == ChromaSiting::TopLeft || v.siting == ChromaSiting::Top ? 0
                     : v.siting == ChromaSiting::BottomLeft || v.siting == ChromaSiting::Bottom
                         ? 256
                         : 128;
    SwsContext* s = scaler(info_.size, from, planar_, left ? 0 : 128, vpos, -513, -513);
    if (!s) fail("its frames cannot be made RGB");
    const bool full = from_full_range_;
    sws_setColorspaceDetails(s, sws_getCoefficients(yuv_ ? matrix_ : SWS_CS_DEFAULT), full,
                             sws_getCoefficients(SWS_CS_DEFAULT), 1, 0, 1 << 16, 1 << 16);
    return s;
  }

  // The frame's time in the stream's time base (where it has none, the last one's plus its
  // duration).
  int64_t frame_time() const {
    if (frame_->best_effort_timestamp != AV_NOPTS_VALUE) return frame_->best_effort_timestamp;
#if LIBAVUTIL_VERSION_INT >= AV_VERSION_INT(57, 30, 100)  // (FFmpeg 6.0: pkt_duration renamed)
    const int64_t duration = frame_->duration;
#else
    const int64_t duration = frame_->pkt_duration;
#endif
    return last_pts_ == AV_NOPTS_VALUE ? 0 : last_pts_ + std::max<int64_t>(duration, 1);
  }

  void take_rgb(VideoFrame& out) {
    const VideoPixels& px = info_.pixels;
    if (!sws_ || sws_from_ != frame_->format) {
      sws_freeContext(sws_);
      sws_from_ = frame_->format;
      sws_ = rgb_scaler(static_cast<AVPixelFormat>(frame_->format));
    }
    Image& im = out.planes[0];
    const int channels = px.alpha ? 4 : 3;
    const PixelType type = px.bits > 8 ? PixelType::U16 : PixelType::U8;
    if (im.is_view() || im.size() != info_.size || im.channels() != channels || im.type() != type)
      im = Image(info_.size, channels, type, px.alpha ? 3 : -1, Image::Unfilled{});
    out.owner.reset();
    uint8_t* dst[4] = {im.data(), nullptr, nullptr, nullptr};
    const int stride[4] = {static_cast<int>(im.row_bytes()), 0, 0, 0};
    if (sws_scale(sws_, frame_->data, frame_->linesize, 0, frame_->height, dst, stride) < 0)
      fail("its frames cannot be made RGB");
    const int64_t pts = frame_time();
    last_pts_ = pts;
    out.pts = pts - start_shift();
  }

  int64_t start_shift() const {
    return range_.start > 0
               ? av_rescale_q(static_cast<int64_t>(std::llround(range_.start * AV_TIME_BASE)),
                              AV_TIME_BASE_Q, fmt_->streams[info_.stream]->time_base)
               : 0;
  }

  // Whether a copied stream's packet is in the range (by its presentation time).
  bool in_range(const AVPacket& p) const {
    if (range_.start <= 0 && std::isinf(range_.end)) return true;
    const int64_t ts = p.pts != AV_NOPTS_VALUE ? p.pts : p.dts;
    if (ts == AV_NOPTS_VALUE) return false;
    const double t = static_cast<double>(ts) * av_q2d(fmt_->streams[p.stream_index]->time_base);
    return t >= range_.start && t < range_.end;
  }

  // A time counted from the range's start.
  void shift(AVPacket& p, AVRational tb) const {
    if (range_.start <= 0) return;
    const int64_t by = av_rescale_q(static_cast<int64_t>(std::llround(range_.start * AV_TIME_BASE)),
                                    AV_TIME_BASE_Q, tb);
    if (p.pts != AV_NOPTS_VALUE) p.pts -= by;
    if (p.dts != AV_NOPTS_VALUE) p.dts -= by;
  }

  // frame_ into out's planes (made planar first where it is not).
  void take(VideoFrame& out) {
    if (frame_->width != info_.size.width || frame_->height != info_.size.height)
      fail("its frame size changes mid-stream (" + std::to_string(frame_->width) + "x" +
           std::to_string(frame_->height) + "), which panoproj does not follow");
    if ((frame_->flags & AV_FRAME_FLAG_CORRUPT) || frame_->decode_error_flags) ++concealed_;
    const AVFrame* src = frame_;
    if (info_.pixels.packed) return take_rgb(out);
    if (frame_->format != planar_) {
      sws_ = sws_getCachedContext(sws_, frame_->width, frame_->height,
                                  static_cast<AVPixelFormat>(frame_->format), frame_->width,
                                  frame_->height, planar_, SWS_POINT, nullptr, nullptr, nullptr);
      if (!planar_frame_) planar_frame_.reset(av_frame_alloc());
      AVFrame* p = planar_frame_.get();
      if (p->width != frame_->width || !p->data[0]) {
        av_frame_unref(p);
        p->format = planar_, p->width = frame_->width, p->height = frame_->height;
        if (av_frame_get_buffer(p, 0) < 0) fail("out of memory");
      }
      if (!sws_ || sws_scale(sws_, frame_->data, frame_->linesize, 0, frame_->height, p->data,
                             p->linesize) < 0)
        fail("its pixel format cannot be made planar");
      src = p;
    }
    const VideoPixels& px = info_.pixels;
    const PixelType type = px.bits > 8 ? PixelType::U16 : PixelType::U8;
    // Rows back to back (no padding): the planes are views of the decoder's buffers, held.
    bool dense = src == frame_;
    for (int c = 0; c < px.planes; ++c)
      dense = dense && src->linesize[c] == px.plane_size(info_.size, c).width *
                                               static_cast<int64_t>(bytes_of(type));
    if (dense) {
      AVFrame* held = av_frame_clone(frame_);
      if (!held) fail("out of memory");
      out.owner = std::shared_ptr<void>(held, [](void* f) {
        auto* p = static_cast<AVFrame*>(f);
        av_frame_free(&p);
      });
      for (int c = 0; c < px.planes; ++c)
        out.planes[static_cast<size_t>(c)] =
            Image::view(held->data[c], px.plane_size(info_.size, c), 1, type);
    }
    if (!dense) out.owner.reset();
    for (int c = 0; c < px.planes && !dense; ++c) {
      const Size s = px.plane_size(info_.size, c);
      Image& im = out.planes[static_cast<size_t>(c)];
      if (im.is_view() || im.size() != s || im.type() != type || im.channels() != 1)
        im = Image(s, 1, type, -1, Image::Unfilled{});
      for (int64_t y = 0; y < s.height; ++y)
        std::memcpy(im.row(y), src->data[c] + y * src->linesize[c], im.row_bytes());
    }
    const int64_t pts = frame_time();
    last_pts_ = pts;
    out.pts = pts - start_shift();
  }

  struct FrameFree {
    void operator()(AVFrame* f) const { av_frame_free(&f); }
  };

  std::string path_;
  bool copy_;
  VideoRange range_;
  int skip_;
  AVFormatContext* fmt_ = nullptr;
  AVCodecContext* dec_ = nullptr;
  AVPacket* packet_ = nullptr;
  AVFrame* frame_ = nullptr;
  std::unique_ptr<AVFrame, FrameFree> planar_frame_;
  SwsContext* sws_ = nullptr;
  AVPixelFormat planar_ = AV_PIX_FMT_NONE;
  int sws_from_ = -1;  // the format sws_ converts from (RGB frames)
  bool yuv_ = false, from_full_range_ = false;
  int matrix_ = AVCOL_SPC_UNSPECIFIED;
  VideoInfo info_;
  PacketQueue queue_;
  bool at_end_ = false;
  AVFrame* pending_ = nullptr;  // the range's first frame, decoded ahead (prime)
  int64_t concealed_ = 0;
  int64_t last_pts_ = AV_NOPTS_VALUE;
};

// libavformat's output through a file descriptor (the temporary the library made).
#if LIBAVFORMAT_VERSION_MAJOR >= 61  // (FFmpeg 7.0: the buffer is const)
int write_fd(void* opaque, const uint8_t* buf, int size) {
#else
int write_fd(void* opaque, uint8_t* buf, int size) {
#endif
  const int fd = *static_cast<int*>(opaque);
  int done = 0;
  while (done < size) {
    const ssize_t n = ::write(fd, buf + done, static_cast<size_t>(size - done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return AVERROR(n < 0 ? errno : ENOSPC);
    done += static_cast<int>(n);
  }
  return size;
}
int64_t seek_fd(void* opaque, int64_t offset, int whence) {
  const int fd = *static_cast<int*>(opaque);
  if (whence == AVSEEK_SIZE) {
    const off_t at = ::lseek(fd, 0, SEEK_CUR), end = ::lseek(fd, 0, SEEK_END);
    ::lseek(fd, at, SEEK_SET);
    return end;
  }
  const off_t r = ::lseek(fd, offset, whence & ~AVSEEK_FORCE);
  return r < 0 ? AVERROR(errno) : r;
}

// The source's data streams a container takes by their tag (GoPro's telemetry into MP4 and MOV).
bool takes_data(const AVOutputFormat* f, const OtherStream& s) {
  const bool mov = std::strcmp(f->name, "mp4") == 0 || std::strcmp(f->name, "mov") == 0;
  return mov && s.tag == "gpmd";
}

// A stream's side data of `type` (HDR10's mastering display and light level): its bytes, or
// none. (FFmpeg 6.1 moved it to codecpar->coded_side_data; 7.0 removed the stream calls.)
std::string stream_side_data(const AVStream* st, AVPacketSideDataType type) {
#if LIBAVFORMAT_VERSION_INT >= AV_VERSION_INT(60, 15, 100)
  const AVPacketSideData* sd = av_packet_side_data_get(st->codecpar->coded_side_data,
                                                       st->codecpar->nb_coded_side_data, type);
  return sd ? std::string(reinterpret_cast<const char*>(sd->data), sd->size) : std::string();
#else
  size_t size = 0;
  const uint8_t* data = av_stream_get_side_data(st, type, &size);
  return data ? std::string(reinterpret_cast<const char*>(data), size) : std::string();
#endif
}

bool set_stream_side_data(AVStream* st, AVPacketSideDataType type, const std::string& bytes) {
#if LIBAVFORMAT_VERSION_INT >= AV_VERSION_INT(60, 15, 100)
  AVPacketSideData* sd = av_packet_side_data_new(
      &st->codecpar->coded_side_data, &st->codecpar->nb_coded_side_data, type, bytes.size(), 0);
  if (!sd) return false;
  std::memcpy(sd->data, bytes.data(), bytes.size());
#else
  uint8_t* data = av_stream_new_side_data(st, type, bytes.size());
  if (!data) return false;
  std::memcpy(data, bytes.data(), bytes.size());
#endif
  return true;
}

// The stream's spherical mapping and stereo layout (none where it has neither).
SphericalVideo spherical_of(const AVStream* st) {
  SphericalVideo v;
  const std::string map = stream_side_data(st, AV_PKT_DATA_SPHERICAL);
  if (map.size() >= sizeof(AVSphericalMapping)) {
    AVSphericalMapping m;
    std::memcpy(&m, map.data(), sizeof m);
    const char* name = av_spherical_projection_name(m.projection);
    v.name = name ? name : "unknown";
    v.kind = m.projection == AV_SPHERICAL_EQUIRECTANGULAR ||
                     m.projection == AV_SPHERICAL_EQUIRECTANGULAR_TILE
                 ? SphericalVideo::Kind::Equirect
             : m.projection == AV_SPHERICAL_CUBEMAP ? SphericalVideo::Kind::Cubemap
                                                    : SphericalVideo::Kind::Other;
    if (m.projection == AV_SPHERICAL_EQUIRECTANGULAR_TILE) {
      constexpr double kUnit = 4294967295.0;  // (0.32 fixed point, UINT32_MAX as 1 as FFmpeg's)
      v.top = m.bound_top / kUnit, v.bottom = m.bound_bottom / kUnit;
      v.left = m.bound_left / kUnit, v.right = m.bound_right / kUnit;
    }
    v.padding = m.padding;
    v.yaw = m.yaw / 65536.0, v.pitch = m.pitch / 65536.0, v.roll = m.roll / 65536.0;
  }
  const std::string stereo = stream_side_data(st, AV_PKT_DATA_STEREO3D);
  if (stereo.size() >= sizeof(AVStereo3D)) {
    AVStereo3D s;
    std::memcpy(&s, stereo.data(), sizeof s);
    const bool inverted = (s.flags & AV_STEREO3D_FLAG_INVERT) != 0;
    const char* name = av_stereo3d_type_name(s.type);
    v.stereo_name = std::string(name ? name : "unknown") + (inverted ? " (inverted)" : "");
    v.stereo = s.type == AV_STEREO3D_2D                        ? SphericalVideo::Stereo::Mono
               : s.type == AV_STEREO3D_TOPBOTTOM && !inverted  ? SphericalVideo::Stereo::TopBottom
               : s.type == AV_STEREO3D_SIDEBYSIDE && !inverted ? SphericalVideo::Stereo::LeftRight
                                                               : SphericalVideo::Stereo::Other;
  }
  return v;
}

// The side data of `v` on the output's stream; false out of memory.
bool set_spherical(AVStream* st, const SphericalVideo& v) {
  if (v.kind != SphericalVideo::Kind::None) {
    size_t size = 0;
    AVSphericalMapping* m = av_spherical_alloc(&size);
    if (!m) return false;
    const bool tile = v.top > 0 || v.bottom > 0 || v.left > 0 || v.right > 0;
    m->projection = v.kind == SphericalVideo::Kind::Cubemap ? AV_SPHERICAL_CUBEMAP
                    : tile                                  ? AV_SPHERICAL_EQUIRECTANGULAR_TILE
                                                            : AV_SPHERICAL_EQUIRECTANGULAR;
    // (Floored: ffprobe's pixel bounds, av_spherical_tile_bounds, round up.)
    const auto bound = [](double f) {
      return static_cast<uint32_t>(std::floor(std::clamp(f, 0.0, 1.0) * 4294967295.0));
    };
    m->bound_top = bound(v.top), m->bound_bottom = bound(v.bottom);
    m->bound_left = bound(v.left), m->bound_right = bound(v.right);
    m->padding = static_cast<uint32_t>(v.padding);
    m->yaw = static_cast<int32_t>(std::llround(v.yaw * 65536));
    m->pitch = static_cast<int32_t>(std::llround(v.pitch * 65536));
    m->roll = static_cast<int32_t>(std::llround(v.roll * 65536));
    const bool ok = set_stream_side_data(st, AV_PKT_DATA_SPHERICAL,
                                         std::string(reinterpret_cast<const char*>(m), size));
    av_free(m);
    if (!ok) return false;
  }
  if (v.stereo == SphericalVideo::Stereo::TopBottom ||
      v.stereo == SphericalVideo::Stereo::LeftRight) {
    AVStereo3D* s = av_stereo3d_alloc();
    if (!s) return false;
    s->type = v.stereo == SphericalVideo::Stereo::TopBottom ? AV_STEREO3D_TOPBOTTOM
                                                            : AV_STEREO3D_SIDEBYSIDE;
    const bool ok = set_stream_side_data(st, AV_PKT_DATA_STEREO3D,
                                         std::string(reinterpret_cast<const char*>(s), sizeof *s));
    av_free(s);
    if (!ok) return false;
  }
  return true;
}

// x265's master-display and max-cll parameters from HDR10's side data ("" where none).
std::string x265_hdr_params(const std::string& mastering, const std::string& light) {
  std::string out;
  if (mastering.size() >= sizeof(AVMasteringDisplayMetadata)) {
    AVMasteringDisplayMetadata m;
    std::memcpy(&m, mastering.data(), sizeof m);
    if (m.has_primaries && m.has_luminance) {
      // In 1/50000 for the chromaticities, 1/10000 cd/m2 for luminance (x265's units); G, B, R.
      auto c = [](AVRational r) { return std::to_string(av_rescale(r.num, 50000, r.den)); };
      auto l = [](AVRational r) { return std::to_string(av_rescale(r.num, 10000, r.den)); };
      out += "master-display=G(" + c(m.display_primaries[1][0]) + "," +
             c(m.display_primaries[1][1]) + ")B(" + c(m.display_primaries[2][0]) + "," +
             c(m.display_primaries[2][1]) + ")R(" + c(m.display_primaries[0][0]) + "," +
             c(m.display_primaries[0][1]) + ")WP(" + c(m.white_point[0]) + "," +
             c(m.white_point[1]) + ")L(" + l(m.max_luminance) + "," + l(m.min_luminance) + ")";
    }
  }
  if (light.size() >= sizeof(AVContentLightMetadata)) {
    AVContentLightMetadata l;
    std::memcpy(&l, light.data(), sizeof l);
    out += std::string(out.empty() ? "" : ":") + "max-cll=" + std::to_string(l.MaxCLL) + "," +
           std::to_string(l.MaxFALL);
  }
  return out;
}

// A GoPro MAX .360's two strips (gopro_max.hpp): its two video streams of one size (the largest
// size two share; the lower index first), each decoded by its own reader, their frames stacked
// in step into one frame of twice the height. The first reader copies the other streams.
class FfPairReader final : public VideoReader {
 public:
  FfPairReader(const std::string& path, bool copy, const VideoRange& range, bool rgb) {
    const auto [a, b] = strips(path);
    first_ = std::make_unique<FfReader>(path, a.ordinal, copy, range, rgb, b.index);
    second_ = std::make_unique<FfReader>(path, b.ordinal, false, range, rgb, -1);
    info_ = first_->info();
    const VideoInfo& i2 = second_->info();
    if (i2.size != info_.size || i2.pixels.pixel_format != info_.pixels.pixel_format)
      throw Error("cannot read " + path + ": its strips' streams " + std::to_string(a.index) +
                      " and " + std::to_string(b.index) + " decode to " +
                      info_.pixels.pixel_format + " and " + i2.pixels.pixel_format +
                      " frames (expected one format)",
                  ErrorKind::File);
    info_.size.height *= 2;
    info_.spherical = {};
  }

  const VideoInfo& info() const override { return info_; }
  int64_t concealed() const override { return first_->concealed() + second_->concealed(); }
  FfReader& first() { return *first_; }

  bool read(VideoFrame& out) override {
    if (!first_->read(a_) || !second_->read(b_)) return false;
    const VideoPixels& px = info_.pixels;
    for (int c = 0; c < px.planes; ++c) {
      const Image& top = a_.planes[static_cast<size_t>(c)];
      const Image& bottom = b_.planes[static_cast<size_t>(c)];
      Image& im = out.planes[static_cast<size_t>(c)];
      const Size s{top.width(), 2 * top.height()};
      if (im.is_view() || im.size() != s || im.type() != top.type() ||
          im.channels() != top.channels())
        im = Image(s, top.channels(), top.type(), top.alpha_channel(), Image::Unfilled{});
      for (int64_t y = 0; y < top.height(); ++y) {
        std::memcpy(im.row(y), top.row(y), top.row_bytes());
        std::memcpy(im.row(top.height() + y), bottom.row(y), bottom.row_bytes());
      }
    }
    out.owner.reset();
    out.pts = a_.pts;
    return true;
  }

 private:
  struct Strip {
    int index = -1, ordinal = -1;  // the stream's index, its place among the video streams
  };
  // The two video streams of the largest size two share (from the header, no frame decoded).
  static std::array<Strip, 2> strips(const std::string& path) {
    AVFormatContext* f = nullptr;
    const int err = avformat_open_input(&f, path.c_str(), nullptr, nullptr);
    if (err < 0)
      throw Error("cannot read " + path + ": it is not a video libavformat can read (" +
                      av_error(err) + ")",
                  ErrorKind::File);
    struct Video {
      Strip strip;
      int64_t w, h;
    };
    std::vector<Video> videos;
    for (unsigned i = 0; i < f->nb_streams; ++i) {
      const AVStream* st = f->streams[i];
      if (st->codecpar->codec_type != AVMEDIA_TYPE_VIDEO ||
          (st->disposition & AV_DISPOSITION_ATTACHED_PIC))
        continue;
      videos.push_back({{static_cast<int>(i), static_cast<int>(videos.size())},
                        st->codecpar->width,
                        st->codecpar->height});
    }
    avformat_close_input(&f);
    std::array<Strip, 2> best{};
    int64_t area = 0;
    for (size_t i = 0; i < videos.size(); ++i)
      for (size_t j = i + 1; j < videos.size(); ++j)
        if (videos[i].w == videos[j].w && videos[i].h == videos[j].h &&
            videos[i].w * videos[i].h > area)
          best = {videos[i].strip, videos[j].strip}, area = videos[i].w * videos[i].h;
    if (area > 0) return best;
    std::string sizes;
    for (const Video& v : videos)
      sizes += (sizes.empty() ? "" : ", ") + std::to_string(v.w) + "x" + std::to_string(v.h);
    throw Error("cannot read " + path + ": it has " + std::to_string(videos.size()) +
                    " video stream" + (videos.size() == 1 ? "" : "s") +
                    (sizes.empty() ? "" : " (" + sizes + ")") +
                    ", not a GoPro MAX's two strips (two video streams of one size)",
                ErrorKind::File);
  }

  std::unique_ptr<FfReader> first_, second_;
  VideoFrame a_, b_;
  VideoInfo info_;
};

class FfWriter final : public VideoWriter {
 public:
  FfWriter(int fd, const std::string& path, const VideoSettings& s, FfReader* from)
      : fd_(fd), path_(path), from_(from) {
    try {  // (a constructor that throws runs no destructor)
      open(s);
    } catch (...) {
      release();
      throw;
    }
  }

  ~FfWriter() override { release(); }

  void open(const VideoSettings& s) {
    const std::string& path = path_;
    int err = avformat_alloc_output_context2(&fmt_, nullptr, nullptr, path.c_str());
    if (err < 0 || !fmt_) fail("no muxer takes its extension");
    const AVCodec* codec = avcodec_find_encoder_by_name(s.codec.c_str());
    if (!codec) fail("these FFmpeg libraries have no encoder " + s.codec);
    if (from_) read_hdr();
    open_encoder(codec, s);
    video_ = avformat_new_stream(fmt_, nullptr);
    if (!video_ || avcodec_parameters_from_context(video_->codecpar, enc_) < 0)
      fail("its video stream cannot be set up");
    video_->time_base = enc_->time_base;
    video_->avg_frame_rate = enc_->framerate;
    if (from_) add_copied();
    if ((!mastering_.empty() &&
         !set_stream_side_data(video_, AV_PKT_DATA_MASTERING_DISPLAY_METADATA, mastering_)) ||
        (!light_.empty() &&
         !set_stream_side_data(video_, AV_PKT_DATA_CONTENT_LIGHT_LEVEL, light_)) ||
        !set_spherical(video_, s.spherical))
      fail("out of memory");
    // (libavformat 5.1's MP4 muxer writes sv3d and st3d only at this compliance level.)
    if (s.spherical.any()) fmt_->strict_std_compliance = FF_COMPLIANCE_UNOFFICIAL;
    spherical_ = s.spherical;
    const size_t buffer_bytes = 1 << 16;
    auto* buffer = static_cast<unsigned char*>(av_malloc(buffer_bytes));
    io_ = avio_alloc_context(buffer, static_cast<int>(buffer_bytes), 1, &fd_, nullptr, write_fd,
                             seek_fd);
    if (!io_) fail("out of memory");
    fmt_->pb = io_;
    fmt_->flags |= AVFMT_FLAG_CUSTOM_IO;
    err = avformat_write_header(fmt_, nullptr);
    if (err < 0) fail("its header cannot be written (" + av_error(err) + ")");
    packet_ = av_packet_alloc();
    frame_ = av_frame_alloc();
  }

  void release() {
    av_frame_free(&frame_);
    av_frame_free(&converted_);
    av_packet_free(&packet_);
    avcodec_free_context(&enc_);
    if (io_) av_freep(&io_->buffer);
    avio_context_free(&io_);
    avformat_free_context(fmt_);
    fmt_ = nullptr;
    sws_freeContext(sws_);
    sws_ = nullptr;
  }

  void write(const VideoFrame& f) override {
    AVFrame* fr = frame_;
    av_frame_unref(fr);
    fr->format = given_, fr->width = static_cast<int>(size_.width),
    fr->height = static_cast<int>(size_.height);
    if (av_frame_get_buffer(fr, 0) < 0) fail("out of memory");
    for (int c = 0; c < pixels_.planes; ++c) {
      const Image& im = f.planes[static_cast<size_t>(c)];
      for (int64_t y = 0; y < im.height(); ++y)
        std::memcpy(fr->data[c] + y * fr->linesize[c], im.row(y), im.row_bytes());
    }
    if (given_ != enc_->pix_fmt) {
      av_frame_unref(converted_);
      converted_->format = enc_->pix_fmt, converted_->width = fr->width,
      converted_->height = fr->height;
      if (av_frame_get_buffer(converted_, 0) < 0) fail("out of memory");
      if (sws_scale(sws_, fr->data, fr->linesize, 0, fr->height, converted_->data,
                    converted_->linesize) < 0)
        fail("its frames cannot be converted to " +
             std::string(av_get_pix_fmt_name(enc_->pix_fmt)));
      fr = converted_;
    }
    fr->pts = f.pts;
    fr->color_range = enc_->color_range, fr->colorspace = enc_->colorspace;
    fr->color_primaries = enc_->color_primaries, fr->color_trc = enc_->color_trc;
    fr->chroma_location = enc_->chroma_sample_location;
    encode(fr);
    copy_queued();
  }

  void finish() override {
    encode(nullptr);
    copy_queued();
    const int err = av_write_trailer(fmt_);
    if (err < 0) fail("writing its index (" + av_error(err) + ")");
    avio_flush(io_);
    if (io_->error < 0) fail(av_error(io_->error));
  }

  const std::vector<std::string>& notes() const override { return notes_; }
  SphericalVideo spherical() const override { return spherical_; }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw Error("cannot write " + path_ + ": " + why, ErrorKind::File);
  }

  void open_encoder(const AVCodec* codec, const VideoSettings& s) {
    enc_ = avcodec_alloc_context3(codec);
    if (!enc_) fail("out of memory");
    size_ = s.size, pixels_ = s.pixels;
    given_ = av_get_pix_fmt(s.pixels.pixel_format.c_str());
    enc_->pix_fmt = given_;
    if (s.pixels.packed) return open_rgb_encoder(codec, s);
    if (codec->pix_fmts) {  // the encoder's nearest where it lacks the planes' format
      bool takes = false;
      for (const AVPixelFormat* f = codec->pix_fmts; *f != AV_PIX_FMT_NONE; ++f)
        takes |= *f == given_;
      if (!takes) {
        enc_->pix_fmt = avcodec_find_best_pix_fmt_of_list(codec->pix_fmts, given_, 0, nullptr);
        sws_ = sws_getContext(static_cast<int>(size_.width), static_cast<int>(size_.height), given_,
                              static_cast<int>(size_.width), static_cast<int>(size_.height),
                              enc_->pix_fmt, SWS_BICUBIC | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT,
                              nullptr, nullptr, nullptr);
        converted_ = av_frame_alloc();
        if (!sws_ || !converted_)
          fail("its pixel format " + s.pixels.pixel_format + " cannot be converted for " + s.codec);
        notes_.push_back("encoder " + s.codec + " takes no " + s.pixels.pixel_format +
                         ": written as " + av_get_pix_fmt_name(enc_->pix_fmt));
      }
    }
    configure(s);
  }

  // Packed RGB frames (images): made 4:2:0 BT.709 limited range where the encoder takes it (8 or
  // 10 bits by the samples' depth), else its nearest format.
  void open_rgb_encoder(const AVCodec* codec, const VideoSettings& s) {
    const AVPixelFormat want = s.pixels.bits > 8 ? AV_PIX_FMT_YUV420P10LE : AV_PIX_FMT_YUV420P;
    enc_->pix_fmt = codec->pix_fmts
                        ? avcodec_find_best_pix_fmt_of_list(codec->pix_fmts, given_, 0, nullptr)
                        : want;
    for (const AVPixelFormat* f = codec->pix_fmts; f && *f != AV_PIX_FMT_NONE; ++f)
      if (*f == want) enc_->pix_fmt = want;
    const AVPixFmtDescriptor* d = av_pix_fmt_desc_get(enc_->pix_fmt);
    const bool yuv = d && !(d->flags & AV_PIX_FMT_FLAG_RGB) && d->nb_components >= 3;
    sws_ = scaler(s.size, given_, enc_->pix_fmt, -513, -513, 0,
                  128);  // (chroma sited left, as H.264's)
    converted_ = av_frame_alloc();
    if (!sws_ || !converted_)
      fail("its frames cannot be converted to " + std::string(av_get_pix_fmt_name(enc_->pix_fmt)));
    sws_setColorspaceDetails(sws_, sws_getCoefficients(SWS_CS_DEFAULT), 1,
                             sws_getCoefficients(SWS_CS_ITU709), yuv ? 0 : 1, 0, 1 << 16, 1 << 16);
    VideoSettings tagged = s;
    tagged.pixels.full_range = !yuv;
    tagged.pixels.matrix = yuv ? AVCOL_SPC_BT709 : AVCOL_SPC_RGB;
    tagged.pixels.primaries = AVCOL_PRI_BT709,
    tagged.pixels.transfer = AVCOL_TRC_IEC61966_2_1;  // sRGB's curve
    tagged.pixels.siting = ChromaSiting::Left, tagged.pixels.siting_said = yuv;
    configure(tagged);
  }

  // The encoder's size, times, colour and rate, then opened.
  void configure(const VideoSettings& s) {
    const AVCodec* codec = enc_->codec;
    enc_->width = static_cast<int>(size_.width), enc_->height = static_cast<int>(size_.height);
    enc_->sample_aspect_ratio = {1, 1};
    enc_->time_base = {s.time_base[0], s.time_base[1]};
    enc_->framerate = {s.frame_rate[0], s.frame_rate[1]};
    enc_->color_range = s.pixels.full_range ? AVCOL_RANGE_JPEG : AVCOL_RANGE_MPEG;
    enc_->colorspace = static_cast<AVColorSpace>(s.pixels.matrix);
    enc_->color_primaries = static_cast<AVColorPrimaries>(s.pixels.primaries);
    enc_->color_trc = static_cast<AVColorTransferCharacteristic>(s.pixels.transfer);
    enc_->chroma_sample_location = s.pixels.siting_said
                                       ? static_cast<AVChromaLocation>(s.pixels.siting)
                                       : AVCHROMA_LOC_UNSPECIFIED;
    if (s.gop > 0) enc_->gop_size = s.gop;
    if (s.bitrate > 0) enc_->bit_rate = s.bitrate;
    enc_->thread_count = s.threads;
    if (fmt_->oformat->flags & AVFMT_GLOBALHEADER) enc_->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    AVDictionary* opts = nullptr;
    if (s.crf >= 0 && s.bitrate == 0) av_dict_set_int(&opts, "crf", s.crf, 0);
    if (!s.preset.empty()) av_dict_set(&opts, "preset", s.preset.c_str(), 0);
    if (const std::string hdr = x265_hdr_params(mastering_, light_);
        !hdr.empty() && std::strcmp(codec->name, "libx265") == 0)
      av_dict_set(&opts, "x265-params", ("hdr10=1:" + hdr).c_str(), 0);
    const int err = avcodec_open2(enc_, codec, &opts);
    AVDictionaryEntry* unused = av_dict_get(opts, "", nullptr, AV_DICT_IGNORE_SUFFIX);
    const std::string left = unused ? unused->key : "";
    av_dict_free(&opts);
    if (err < 0) {
      std::string given = "; " + std::to_string(size_.width) + "x" + std::to_string(size_.height) +
                          " " + av_get_pix_fmt_name(enc_->pix_fmt);
      if (s.crf >= 0) given += ", crf " + std::to_string(s.crf);
      if (s.bitrate > 0) given += ", bit rate " + std::to_string(s.bitrate);
      if (!s.preset.empty()) given += ", preset " + s.preset;
      if (s.gop > 0) given += ", gop " + std::to_string(s.gop);
      fail("encoder " + s.codec + " refuses these settings (" + av_error(err) + given +
           ")");  // (its own log is off)
    }
    if (!left.empty()) fail("encoder " + s.codec + " has no option " + left);
  }

  // HDR10's static metadata (mastering display, content light level) as the source's container
  // says it: on the output's stream (the muxer's boxes or elements) and, for x265, in its SEI.
  void read_hdr() {
    const AVStream* in = from_->format()->streams[from_->info().stream];
    mastering_ = stream_side_data(in, AV_PKT_DATA_MASTERING_DISPLAY_METADATA);
    light_ = stream_side_data(in, AV_PKT_DATA_CONTENT_LIGHT_LEVEL);
    // (Else the first frame's: HEVC's SEI, which libx265's FFmpeg wrapper does not export to a
    // container; both structures are the same in a frame's and a stream's side data.)
    if (mastering_.empty())
      mastering_ = from_->first_frame_side_data(AV_FRAME_DATA_MASTERING_DISPLAY_METADATA);
    if (light_.empty()) light_ = from_->first_frame_side_data(AV_FRAME_DATA_CONTENT_LIGHT_LEVEL);
  }

  // A stream for each other stream of the source the container takes; one note for each dropped.
  void add_copied() {
    const AVFormatContext* in = from_->format();
    const AVStream* video_in = in->streams[from_->info().stream];
    // The start timecode (a tmcd track, which libavformat 5.1 cannot copy into MP4) made again
    // from the source's.
    const AVDictionaryEntry* tc = av_dict_get(video_in->metadata, "timecode", nullptr, 0);
    for (const OtherStream& o : from_->info().others) {
      const AVStream* st = in->streams[o.index];
      if (!tc) tc = av_dict_get(st->metadata, "timecode", nullptr, 0);
      const AVMediaType t = st->codecpar->codec_type;
      const bool media = t == AVMEDIA_TYPE_AUDIO || t == AVMEDIA_TYPE_SUBTITLE;
      // (libavformat 5.1's MP4 muxer lists FLAC and TrueHD but refuses them in its header
      // unless told to write experimental files.)
      const AVCodecID id = st->codecpar->codec_id;
      const bool experimental = std::strcmp(fmt_->oformat->name, "mp4") == 0 &&
                                (id == AV_CODEC_ID_FLAC || id == AV_CODEC_ID_TRUEHD);
      const bool takes =
          media
              ? avformat_query_codec(fmt_->oformat, id, FF_COMPLIANCE_NORMAL) == 1 && !experimental
              : t == AVMEDIA_TYPE_DATA && takes_data(fmt_->oformat, o);
      if (!takes) {
        if (o.tag != "tmcd")
          notes_.push_back(
              "stream " + std::to_string(o.index) + " (" + o.kind + ", " + o.codec +
              (o.tag.empty() ? "" : ", " + o.tag) + ") dropped: " + fmt_->oformat->name +
              " does not take it" +
              (experimental ? " (libavformat 5.1 writes it only as experimental)" : ""));
        continue;
      }
      AVStream* out = avformat_new_stream(fmt_, nullptr);
      if (!out || avcodec_parameters_copy(out->codecpar, st->codecpar) < 0)
        fail("a copied stream cannot be set up");
      out->codecpar->codec_tag = t == AVMEDIA_TYPE_DATA ? st->codecpar->codec_tag : 0;
      out->time_base = st->time_base;
      out->disposition = st->disposition;
      av_dict_copy(&out->metadata, st->metadata, 0);
      copied_.resize(std::max<size_t>(copied_.size(), static_cast<size_t>(o.index) + 1), nullptr);
      copied_[static_cast<size_t>(o.index)] = out;
      if (o.tag == "SA3D" || st->codecpar->ch_layout.nb_channels == 4)
        notes_.push_back("stream " + std::to_string(o.index) + " (" + o.codec +
                         ", 4 channels) copied; its spatial audio box (SA3D), if any, is not "
                         "written by libavformat 5.1");
    }
    if (tc) av_dict_set(&video_->metadata, "timecode", tc->value, 0);
  }

  void encode(const AVFrame* f) {
    int err = avcodec_send_frame(enc_, f);
    if (err < 0) fail("encoding a frame (" + av_error(err) + ")");
    for (;;) {
      err = avcodec_receive_packet(enc_, packet_);
      if (err == AVERROR(EAGAIN) || err == AVERROR_EOF) return;
      if (err < 0) fail("encoding a frame (" + av_error(err) + ")");
      av_packet_rescale_ts(packet_, enc_->time_base, video_->time_base);
      packet_->stream_index = video_->index;
      mux(packet_);
    }
  }

  void copy_queued() {
    if (!from_) return;
    while (AVPacket* p = from_->queue().pop()) {
      const size_t i = static_cast<size_t>(p->stream_index);
      AVStream* out = i < copied_.size() ? copied_[i] : nullptr;
      if (out) {
        av_packet_rescale_ts(p, from_->format()->streams[i]->time_base, out->time_base);
        p->stream_index = out->index;
        p->pos = -1;
        mux(p);
      }
      av_packet_free(&p);
    }
  }

  void mux(AVPacket* p) {
    const int err = av_interleaved_write_frame(fmt_, p);
    if (err < 0)
      fail(io_->error < 0 ? av_error(io_->error) : "muxing a packet (" + av_error(err) + ")");
  }

  int fd_;
  std::string path_;
  FfReader* from_;
  AVFormatContext* fmt_ = nullptr;
  AVIOContext* io_ = nullptr;
  AVCodecContext* enc_ = nullptr;
  AVStream* video_ = nullptr;
  std::vector<AVStream*> copied_;  // by source stream index
  std::string mastering_, light_;  // HDR10's side data of the source's stream, if any
  AVPacket* packet_ = nullptr;
  AVFrame *frame_ = nullptr, *converted_ = nullptr;
  SwsContext* sws_ = nullptr;
  AVPixelFormat given_ = AV_PIX_FMT_NONE;
  Size size_;
  VideoPixels pixels_;
  SphericalVideo spherical_;
  std::vector<std::string> notes_;
};

class FfBackend final : public VideoBackend {
 public:
  FfBackend() { av_log_set_level(AV_LOG_QUIET); }

  std::unique_ptr<VideoReader> open(const std::string& path, int stream, bool copy,
                                    const VideoRange& range, bool rgb) override {
    return std::make_unique<FfReader>(path, stream, copy, range, rgb);
  }

  std::unique_ptr<VideoReader> open_pair(const std::string& path, bool copy,
                                         const VideoRange& range, bool rgb) override {
    return std::make_unique<FfPairReader>(path, copy, range, rgb);
  }

  std::string check_output(const std::string& path, const std::string& codec) override {
    const AVOutputFormat* f = av_guess_format(nullptr, path.c_str(), nullptr);
    if (!f || (f->flags & AVFMT_NOFILE))
      return "no muxer of these FFmpeg libraries takes its extension";
    const AVCodec* c = avcodec_find_encoder_by_name(codec.c_str());
    if (!c) return "these FFmpeg libraries have no encoder " + codec;
    if (avformat_query_codec(f, c->id, FF_COMPLIANCE_NORMAL) != 1)
      return std::string(f->name) + " does not take " + avcodec_get_name(c->id) + " video";
    return "";
  }

  std::unique_ptr<VideoWriter> create(int fd, const std::string& path,
                                      const VideoSettings& settings,
                                      VideoReader* copy_from) override {
    auto* pair = dynamic_cast<FfPairReader*>(copy_from);
    auto* from = pair ? &pair->first() : dynamic_cast<FfReader*>(copy_from);
    return std::make_unique<FfWriter>(fd, path, settings, from && from->copying() ? from : nullptr);
  }

  std::string version() override {
    return std::string("FFmpeg ") + av_version_info() + " (libavformat " +
           AV_STRINGIFY(LIBAVFORMAT_VERSION) + ", libavcodec " + AV_STRINGIFY(LIBAVCODEC_VERSION) +
           ")";
  }
};

}  // namespace
}  // namespace panoproj

extern "C" __attribute__((visibility("default"))) int panoproj_video_abi() {
  return panoproj::kVideoPluginAbi;
}
extern "C" __attribute__((visibility("default"))) panoproj::VideoBackend* panoproj_video_backend() {
  static panoproj::FfBackend backend;
  return &backend;
}
