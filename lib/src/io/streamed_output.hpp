#pragma once
// write_image in two steps, so that an output can be encoded while it is made: parts of the image
// are reported as they become final, and a JPEG encodes the blocks they complete there and then
// (JpegBlockEncoder, codec.hpp); write() encodes the rest and writes the file like write_image.
// Other formats, and samples to be converted first, encode whole in write(). Internal.
#include <memory>
#include <string>

#include "io/codec.hpp"
#include "panoproj/image.hpp"
#include "panoproj/io.hpp"

namespace panoproj {

class StreamedOutput {
 public:
  // The image to come: size, channels, sample type (checked against the format and options now).
  StreamedOutput(std::string path, WriteOptions options, Size size, int channels, PixelType type);
  ~StreamedOutput();
  // Whether done() encodes anything (else it need not be called).
  bool streams() const { return jpeg_ != nullptr; }
  // Pixels r of image are final (each once, from any thread).
  void done(const Image& image, const PixelRect& r);
  // The whole image, as reported: encodes what is left and writes the file.
  void write(const Image& image);

 private:
  std::string path_;
  WriteOptions options_;
  std::unique_ptr<JpegBlockEncoder> jpeg_;
};

}  // namespace panoproj
