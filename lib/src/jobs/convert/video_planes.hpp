#pragma once
// A video frame converted plane by plane in its own format: the luma (and alpha, and RGB) planes
// on the frame's geometry, each subsampled chroma plane on its own at the chroma resolution and
// the sited position of its samples (FFmpeg's chroma location); outside the source's field video
// black (Y at 16 << (bits - 8) for limited range, 0 for full; chroma at mid-scale; alpha 0), and
// samples of 9 to 15 bits clamped to their range. Used by the convert job's video path and by
// Python's VideoPlan (frames decoded by PyAV).
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "io/video_plugin.hpp"
#include "panoproj/convert.hpp"

namespace panoproj {

// An output's chroma subsampling (log2 per axis): the frames' own; 4:2:0 for packed RGB encoded
// (encoded: false for RGB written as images); none for gray.
std::pair<int, int> output_subsampling(const VideoPixels& px, bool encoded);

// The geometry `make` gives for the options, fitted to whole chroma samples of `subsampling` (in
// each eye; for a cube, cells of whole chroma samples): as it is where it holds them; else, where
// the options give no size, the next size that does, with a warning; else Error naming that size.
ConversionGeometry fit_chroma(const VideoPixels& px, std::pair<int, int> subsampling,
                              const ConvertOptions& options,
                              const std::function<ConversionGeometry(const ConvertOptions&)>& make,
                              const std::function<void(const std::string&)>& warn);

// Refuses in one line the options a video's frames cannot take: the reference engine; and where
// they are converted in their own planes (`planes`: not RGB frames written as images), an edge
// fill or an added alpha (pixels without a source are video black).
void check_video_options(const ConvertOptions& options, bool planes);

class VideoPlanes {
 public:
  // `frame`: the luma planes' geometry (fit_chroma's); `input` and `from_text` name the source
  // where its chroma planes cannot hold it (Error).
  VideoPlanes(const VideoPixels& px, const ConversionGeometry& frame, const ConvertOptions& options,
              const std::string& input, const std::string& from_text);
  VideoPlanes(const VideoPlanes&) = delete;
  VideoPlanes& operator=(const VideoPlanes&) = delete;

  // Plane p of a frame into `out` (its buffer reused where it has the plane's size already).
  void convert_plane(int p, const Image& in, Image& out) const;
  void convert(const VideoFrame& in, VideoFrame& out) const;
  // Whether chroma planes have their own geometry (subsampled YUV).
  bool subsampled() const { return chroma_.has_value(); }
  const VideoPixels& pixels() const { return px_; }
  Size source_size() const { return luma_.source_frame(); }
  Size target_size() const { return luma_.target_frame(); }

 private:
  struct PlaneMap {
    const Converter* converter = nullptr;
    std::vector<uint8_t> none;  // 1 where the output sample has no source
    bool any_none = false;
    uint16_t black = 0, most = 0;  // video black; the largest sample
  };
  std::vector<uint8_t> no_source(const Converter& c, Size in) const;

  VideoPixels px_;
  ConversionGeometry luma_;
  std::optional<ConversionGeometry> chroma_;
  std::optional<Converter> luma_converter_, chroma_converter_;
  std::array<PlaneMap, 4> planes_;
};

}  // namespace panoproj
