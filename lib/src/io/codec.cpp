// What every decoder shares (the built-in ones and the OpenImageIO plugin's, which compiles this
// file too).
#include "io/codec.hpp"

#include <new>

#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"

namespace panoproj {

Image window_buffer(const std::string& path, const Decoder& d, PixelRect window, int scale, Image spare) {
  const ImageHeader& h = d.header();
  const Size size = window.size();
  try {
    const bool fits = spare.size() == size && spare.channels() == h.channels && spare.type() == h.type &&
                      spare.alpha_channel() == h.alpha_channel;
    Image img = fits ? std::move(spare) : Image(size, h.channels, h.type, h.alpha_channel, Image::Unfilled{});
    img.set_window(window.x0, window.y0, d.scaled_size(scale));
    return img;
  } catch (const std::bad_alloc&) {
    throw Error("cannot read " + path + ": " + size_text(size) + " pixels (" +
                    bytes_text(image_bytes(size, h.channels, bytes_of(h.type))) + ") cannot be allocated",
                ErrorKind::Memory);
  }
}


void throw_damaged(const std::string& path, const std::string& why) {
  throw Error("cannot read " + path + ": " + one_line(why) + " (the file is damaged or truncated)", ErrorKind::File);
}

}  // namespace panoproj
