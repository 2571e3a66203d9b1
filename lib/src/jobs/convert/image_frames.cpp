#include "jobs/convert/image_frames.hpp"

#include <cmath>

#include "io/atomic_output.hpp"
#include "io/formats.hpp"
#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"

namespace panoproj {
namespace {

class ImageListReader final : public VideoReader {
 public:
  ImageListReader(const std::vector<std::string>& images, double fps) : images_(images) {
    if (images.empty()) throw Error("no input given (expected a video, or images to make one)");
    for (const std::string& path : images) {
      const ImageInfo i = read_image_info(path);
      if (i.type == PixelType::F16 || i.type == PixelType::F32)
        throw Error("input " + path +
                    " has float samples: a video's are integers (write it as 8 or 16 bits first)");
      if (path == images.front()) first_ = i;
      if (i.size != first_.size || i.channels != first_.channels || i.type != first_.type)
        throw Error("input " + path + " (" + size_text(i.size) + ", " + std::to_string(i.channels) +
                    " channels of " + name_of(i.type) + ") differs from " + images.front() + " (" +
                    size_text(first_.size) + ", " + std::to_string(first_.channels) + " of " +
                    name_of(first_.type) + "): a video's frames are alike");
    }
    info_.container = "images";
    info_.codec = format_named(first_.format).title;
    info_.size = first_.size;
    VideoPixels& p = info_.pixels;
    p.packed = true, p.rgb = true, p.full_range = true, p.planes = 1;
    p.alpha = first_.channels == 2 || first_.channels == 4;
    p.bits = first_.type == PixelType::U16 ? 16 : 8;
    p.pixel_format = p.bits > 8 ? (p.alpha ? "rgba64le" : "rgb48le") : (p.alpha ? "rgba" : "rgb24");
    // (Times in thousandths of a frame's time: exact for integer and decimal rates.)
    const auto milli = static_cast<int>(std::llround(fps * 1000));
    info_.time_base[0] = 1000, info_.time_base[1] = milli;
    info_.frame_rate[0] = milli, info_.frame_rate[1] = 1000;
    info_.frames = static_cast<int64_t>(images.size());
    info_.duration = static_cast<double>(images.size()) / fps;
  }

  const VideoInfo& info() const override { return info_; }
  int64_t concealed() const override { return 0; }

  bool read(VideoFrame& frame) override {
    if (next_ >= images_.size()) return false;
    Image im = read_image(images_[next_]);
    if (im.channels() < 3) im = to_rgb(im);
    frame.planes[0] = std::move(im);
    frame.owner.reset();
    frame.pts = static_cast<int64_t>(next_++);
    return true;
  }

 private:
  // Gray (and alpha) as RGB(A).
  static Image to_rgb(const Image& gray) {
    const bool alpha = gray.channels() == 2;
    Image out(gray.size(), alpha ? 4 : 3, gray.type(), alpha ? 3 : -1, Image::Unfilled{});
    const size_t b = bytes_of(gray.type());
    for (int64_t y = 0; y < gray.height(); ++y)
      for (int64_t x = 0; x < gray.width(); ++x) {
        const unsigned char* s = gray.pixel(x, y);
        unsigned char* d = out.pixel(x, y);
        for (int c = 0; c < 3; ++c) std::memcpy(d + c * b, s, b);
        if (alpha) std::memcpy(d + 3 * b, s + b, b);
      }
    return out;
  }

  std::vector<std::string> images_;
  ImageInfo first_;
  VideoInfo info_;
  size_t next_ = 0;
};

class ImageSequenceWriter final : public VideoWriter {
 public:
  ImageSequenceWriter(const std::string& pattern, const WriteOptions& write)
      : pattern_(pattern), write_(write) {
    if (pattern.find("{n}") == std::string::npos)
      throw Error("output " + pattern +
                  " names one image for a video's frames (put {n} in it, e.g. frames/{n}.png)");
    format_of_path(pattern);  // (an image format's extension, else the error naming them)
    check_output_path(path(0), write.overwrite, true);
    folders_.make({path(0)});
  }

  void write(const VideoFrame& frame) override { write_image(frame.planes[0], path(n_++), write_); }
  void finish() override { folders_.keep(); }
  const std::vector<std::string>& notes() const override { return notes_; }

 private:
  std::string path(int64_t n) const {
    std::string s = pattern_;
    for (size_t at; (at = s.find("{n}")) != std::string::npos;) s.replace(at, 3, std::to_string(n));
    return s;
  }

  std::string pattern_;
  WriteOptions write_;
  MadeFolders folders_;  // the pattern's missing folders, removed again if the job fails
  int64_t n_ = 0;
  std::vector<std::string> notes_;
};

}  // namespace

std::unique_ptr<VideoReader> image_list_reader(const std::vector<std::string>& images, double fps) {
  return std::make_unique<ImageListReader>(images, fps);
}

std::unique_ptr<VideoWriter> image_sequence_writer(const std::string& pattern,
                                                   const WriteOptions& write) {
  return std::make_unique<ImageSequenceWriter>(pattern, write);
}

}  // namespace panoproj
