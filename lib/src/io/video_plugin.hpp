#pragma once
// FFmpeg's libraries behind a plugin: libpanoproj_video.so (io/video/backend.cpp) links
// libavformat, libavcodec, libavutil and libswscale; the library does not. It is opened the first
// time a video is named, so the command starts as fast without it and installs without FFmpeg.
// Both sides are built together (kVideoPluginAbi guards against a stale plugin).
//
// Frames cross as planes: one one-channel Image each (uint8 for 8-bit samples, uint16 holding
// the samples' values for 9 to 16 bits), Y Cb Cr or G B R and alpha if any, the chroma planes at
// their subsampled size; packed and semi-planar formats are made planar (swscale: the same
// values, moved).
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "panoproj/image.hpp"

namespace panoproj {

// Where a 4:2:x chroma sample sits (FFmpeg's AVChromaLocation, in its order).
enum class ChromaSiting { Unspecified, Left, Center, TopLeft, Top, BottomLeft, Bottom };

// A stream's pixels: its planes, their depth and siting, and the colour it declares (FFmpeg's
// enumerations as numbers: kept as they are and handed to the encoder).
struct VideoPixels {
  std::string pixel_format;  // FFmpeg's name of the planar format the planes are in
  int planes = 3;            // 1 (gray), 2 (gray, alpha), 3 or 4 (alpha last)
  bool rgb = false;          // planes G, B, R
  bool alpha = false;        // the last plane is alpha (at the frame's size)
  bool packed = false;       // one plane of interleaved R G B (A) samples (images in and out)
  int bits = 8;              // significant bits a sample (8 ... 16)
  int log2_chroma_w = 0, log2_chroma_h = 0;
  ChromaSiting siting = ChromaSiting::Left;  // where the stream says none, its codec's usual
  bool siting_said = false;                  // the stream says it (an output says it only then)
  bool full_range = false;
  int matrix = 2, primaries = 2,
      transfer = 2;  // AVCOL_SPC_*, AVCOL_PRI_*, AVCOL_TRC_* (2: unspecified)
  // Whether plane p is subsampled (a chroma plane).
  bool chroma(int p) const { return !packed && planes >= 3 && (p == 1 || p == 2); }
  Size plane_size(Size frame, int p) const {
    if (!chroma(p)) return frame;
    return {-(-frame.width >> log2_chroma_w), -(-frame.height >> log2_chroma_h)};
  }
};

// What a stream's coding says of its pixels where the stream does not: chroma centred for JPEG's
// codings (MJPEG, the yuvj formats), else left (MPEG-2, H.264, HEVC); the yuvj formats and RGB
// full range. Sets siting_said from the siting the stream gave (Unspecified: none).
inline void apply_coding_defaults(VideoPixels& v, bool mjpeg) {
  const bool yuvj = v.pixel_format.rfind("yuvj", 0) == 0;
  v.siting_said = v.siting != ChromaSiting::Unspecified;
  if (!v.siting_said) v.siting = mjpeg || yuvj ? ChromaSiting::Center : ChromaSiting::Left;
  v.full_range = v.full_range || yuvj || v.rgb;
}

// Where a frame sits in the sphere, as FFmpeg's libraries carry Google's Spherical Video V2
// (AVSphericalMapping, AVStereo3D): read from MP4's sv3d and st3d boxes (and V1's uuid XML),
// Matroska's Projection and StereoMode; written into the same.
struct SphericalVideo {
  enum class Kind { None, Equirect, Cubemap, Other };
  Kind kind = Kind::None;
  std::string name;  // FFmpeg's name of the projection ("equirectangular", "mesh")
  // Equirect: the fractions of the whole panorama cropped off each edge (the equi box's 0.32
  // fixed-point bounds).
  double top = 0, bottom = 0, left = 0, right = 0;
  int64_t padding = 0;  // Cubemap: pixels of padding at each face's edges (cbmp's)
  // The pose (prhd's, in degrees): yaw counter-clockwise about the up vector, then pitch
  // counter-clockwise about the right vector, then roll clockwise about the forward vector.
  double yaw = 0, pitch = 0, roll = 0;
  enum class Stereo { Mono, TopBottom, LeftRight, Other };
  Stereo stereo = Stereo::Mono;  // left eye first (top, left)
  std::string stereo_name;       // FFmpeg's name of a layout ("side by side (inverted)")
  bool any() const { return kind != Kind::None || stereo != Stereo::Mono; }
};

// Another stream of the file: copied packet for packet, or dropped.
struct OtherStream {
  int index = 0;
  std::string kind;   // "audio", "subtitle", "data", "attachment", "video"
  std::string codec;  // FFmpeg's name ("aac", "bin_data")
  std::string tag;    // its four-character code ("gpmd"), "" if none
};

struct VideoInfo {
  std::string container;  // the demuxer's name
  std::string codec;      // the decoder's name
  int stream = 0;         // the video stream read
  Size size;
  VideoPixels pixels;
  int time_base[2] = {1, 1};        // the stream's
  int frame_rate[2] = {0, 1};       // its average, {0, 1} unknown
  double duration = 0;              // seconds, 0 unknown
  int64_t frames = 0;               // as the container says, 0 unknown
  std::vector<OtherStream> others;  // every other stream
  SphericalVideo spherical;         // the video stream's
};

struct VideoFrame {
  std::array<Image, 4> planes;  // planes beyond VideoPixels::planes are empty
  int64_t pts = 0;              // in the stream's time base
  // What the planes' pixels belong to where they are views (a decoded frame's buffers, held).
  std::shared_ptr<void> owner;
};

// The part of a stream read: the frames (and copied packets) whose time is in [start, end)
// seconds, their times then counted from start.
struct VideoRange {
  double start = 0, end = HUGE_VAL;
};

class VideoReader {
 public:
  virtual ~VideoReader() = default;
  virtual const VideoInfo& info() const = 0;
  // The next frame in presentation order into `frame` (its buffers reused); false at the end.
  // Throws Error naming the file where it cannot go on.
  virtual bool read(VideoFrame& frame) = 0;
  // Packets the decoder reported corrupt and concealed.
  virtual int64_t concealed() const = 0;
};

// What the encoder makes.
struct VideoSettings {
  std::string codec;  // FFmpeg's encoder name ("libx264")
  Size size;
  VideoPixels pixels;          // the planes it is given (the source's, or packed RGB: made
                               // BT.709 limited-range YUV for the encoder)
  int time_base[2] = {1, 25};  // of the frames' pts (the source stream's)
  int frame_rate[2] = {0, 1};  // their average, {0, 1} unknown
  int crf = -1;                // -1: the encoder's default
  int64_t bitrate = 0;         // bits a second, 0: by crf
  std::string preset;          // "" : the encoder's default
  int gop = 0;                 // frames between keyframes, 0: the encoder's default
  int threads = 0;             // the encoder's threads, 0: its choice
  SphericalVideo spherical;    // written where the muxer writes it (MP4, Matroska, WebM)
};

class VideoWriter {
 public:
  virtual ~VideoWriter() = default;
  // Encodes one frame (pts in the source stream's time base), interleaving the packets of the
  // copied streams read meanwhile. Throws Error naming the output.
  virtual void write(const VideoFrame& frame) = 0;
  // Flushes the encoder, copies the rest of the other streams, writes the trailer.
  virtual void finish() = 0;
  // What was dropped (a line each) and copied (their indices in the source).
  virtual const std::vector<std::string>& notes() const = 0;
  // The spherical metadata written (none where the file gets none).
  virtual SphericalVideo spherical() const { return {}; }
};

class VideoBackend {
 public:
  virtual ~VideoBackend() = default;
  // Opens `path` for its video stream `stream` (-1: the first), for the frames of `range` (from
  // the keyframe before its start); throws Error naming the path. copy: its other streams'
  // packets are kept for a writer to copy. rgb: frames as one packed RGB(A) plane of 8 or 16
  // bits (the stream's matrix, range and chroma siting; bicubic chroma), for images.
  virtual std::unique_ptr<VideoReader> open(const std::string& path, int stream, bool copy,
                                            const VideoRange& range = {}, bool rgb = false) = 0;
  // A GoPro MAX .360 (gopro_max.hpp): its two video streams of one size (the largest two share,
  // the lower index first, whatever their indices), decoded in step, each frame the two stacked
  // (the first on top); the other streams as open's (the second strip's neither copied nor
  // listed). Throws Error where the file has no two such streams.
  virtual std::unique_ptr<VideoReader> open_pair(const std::string& path, bool copy,
                                                 const VideoRange& range = {},
                                                 bool rgb = false) = 0;
  // Whether `codec` names an encoder the libraries have, and the muxer of `path`'s extension
  // takes it; "" when so, else why not.
  virtual std::string check_output(const std::string& path, const std::string& codec) = 0;
  // A writer into the open file `fd` (the temporary of `path`, which names the muxer and
  // messages); copying the other streams of `copy_from` (may be null).
  virtual std::unique_ptr<VideoWriter> create(int fd, const std::string& path,
                                              const VideoSettings& settings,
                                              VideoReader* copy_from) = 0;
  // "FFmpeg 5.1.9 (libavformat 59.27.100 ...)".
  virtual std::string version() = 0;
};

// The plugin, loaded on first use as the OpenImageIO plugin is (io/plugin_loader.hpp, beside
// the executable or module ..., $PANOPROJ_VIDEO_PLUGIN). Throws Error saying what is missing,
// naming `why` ("reading a.mp4").
VideoBackend& video_backend(const std::string& why);
// Whether it has been loaded in this process (tests: image jobs never load it).
bool video_loaded();

// A second backend for where the plugin is missing, tried after it: the Python module's, through
// PyAV (python/src/pyav_package.cpp). `get` gives it, or nullptr and why not; `hint` says how to
// install it.
using VideoFallback = VideoBackend* (*)(std::string& why_not);
void set_video_fallback(VideoFallback get, const char* hint);

constexpr int kVideoPluginAbi = 4;

}  // namespace panoproj

extern "C" int panoproj_video_abi();
extern "C" panoproj::VideoBackend* panoproj_video_backend();
