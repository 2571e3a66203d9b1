#pragma once
// write_image in steps, so that an output can be encoded while it is made and written later:
// parts of the image are reported as they become final, and a JPEG encodes the blocks they
// complete there and then (JpegBlockEncoder, codec.hpp); finish() encodes the rest, and the
// EncodedOutput it returns writes the file like write_image. Other formats, and samples to be
// converted first, encode whole in finish(). Internal.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "io/codec.hpp"
#include "panoproj/image.hpp"
#include "panoproj/io.hpp"

namespace panoproj {

// Encoded files not written yet: an output's one, or a face set's six. write() writes them all
// or none (OutputSet: each path checked again), then runs `landed` before a signal acts. A PPM of
// 8-bit samples holds the image's rows, not a copy: the image given to finish() must outlive the
// write.
class EncodedOutput {
 public:
  EncodedOutput();
  ~EncodedOutput();
  EncodedOutput(EncodedOutput&&) noexcept;
  EncodedOutput& operator=(EncodedOutput&&) noexcept;
  void write(const std::function<void()>& landed = {}) const;

  struct Files;  // (io.cpp)
  explicit EncodedOutput(std::unique_ptr<Files> files);

 private:
  std::unique_ptr<Files> files_;
};

// A strip's six faces encoded at once (write_cube_faces, io.hpp, in two steps; the paths are
// checked first).
EncodedOutput encode_cube_faces(const Image& strip, const std::string& pattern, const WriteOptions& options,
                                const FaceOrder& order);

class StreamedOutput {
 public:
  // The image to come: size, channels, sample type (checked against the format and options now).
  StreamedOutput(std::string path, WriteOptions options, Size size, int channels, PixelType type);
  ~StreamedOutput();
  // Whether done() encodes anything (else it need not be called).
  bool streams() const { return jpeg_ != nullptr; }
  // Pixels r of image are final (each once, from any thread).
  void done(const Image& image, const PixelRect& r);
  // The whole image, as reported: encodes what is left.
  EncodedOutput finish(const Image& image);

 private:
  std::string path_;
  WriteOptions options_;
  std::unique_ptr<JpegBlockEncoder> jpeg_;
};

}  // namespace panoproj
