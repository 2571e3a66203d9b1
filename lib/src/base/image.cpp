#include "panoproj/image.hpp"

#include <algorithm>
#include <cstring>

#include "panoproj/error.hpp"
#include "base/sample_io.hpp"

namespace panoproj {

const char* name_of(PixelType t) {
  switch (t) {
    case PixelType::U8: return "uint8";
    case PixelType::U16: return "uint16";
    case PixelType::F16: return "half";
    case PixelType::F32: return "float";
  }
  return "?";
}

double unit_of(PixelType t) {
  switch (t) {
    case PixelType::U8: return 255.0;
    case PixelType::U16: return 65535.0;
    default: return 1.0;
  }
}

Image::Image(Size size, int channels, PixelType type, int alpha_channel)
    : Image(size, channels, type, alpha_channel, Unfilled{}) {
  std::fill(pixels_.begin(), pixels_.end(), 0);
}

namespace {

void check_layout(Size size, int channels, int alpha_channel) {
  if (channels < 1 || channels > 4)
    throw Error("channels: " + std::to_string(channels) + " (expected 1 to 4)");
  if (size.width < 1 || size.height < 1)
    throw Error("image size: " + std::to_string(size.width) + "x" + std::to_string(size.height) +
                " (expected at least 1x1)");
  if (alpha_channel >= channels || alpha_channel < -1)
    throw Error("alpha channel: " + std::to_string(alpha_channel) + " (expected -1 or < " +
                std::to_string(channels) + ")");
}

}  // namespace

Image::Image(Size size, int channels, PixelType type, int alpha_channel, Unfilled)
    : size_(size), channels_(channels), type_(type), alpha_(alpha_channel) {
  check_layout(size, channels, alpha_channel);
  bytes_ = static_cast<size_t>(size.width) * static_cast<size_t>(size.height) * pixel_bytes();
  pixels_.resize(bytes_);
  data_ = pixels_.data();
}

Image Image::view(unsigned char* pixels, Size size, int channels, PixelType type, int alpha_channel) {
  check_layout(size, channels, alpha_channel);
  Image v;
  v.size_ = size, v.channels_ = channels, v.type_ = type, v.alpha_ = alpha_channel;
  v.bytes_ = static_cast<size_t>(size.width) * static_cast<size_t>(size.height) * v.pixel_bytes();
  v.data_ = pixels;
  v.view_ = true;
  return v;
}

Image& Image::operator=(const Image& o) {
  if (this == &o) return *this;
  size_ = o.size_, channels_ = o.channels_, type_ = o.type_, alpha_ = o.alpha_;
  ox_ = o.ox_, oy_ = o.oy_, frame_ = o.frame_, bytes_ = o.bytes_, view_ = o.view_;
  pixels_ = o.pixels_;
  data_ = view_ ? o.data_ : pixels_.data();
  return *this;
}

Image& Image::operator=(Image&& o) noexcept {
  if (this == &o) return *this;
  size_ = o.size_, channels_ = o.channels_, type_ = o.type_, alpha_ = o.alpha_;
  ox_ = o.ox_, oy_ = o.oy_, frame_ = o.frame_, bytes_ = o.bytes_, view_ = o.view_;
  pixels_ = std::move(o.pixels_);
  data_ = o.data_;
  o.size_ = {}, o.frame_ = {}, o.bytes_ = 0, o.ox_ = o.oy_ = 0, o.data_ = nullptr, o.view_ = false;
  o.pixels_.clear();
  return *this;
}

bool Image::operator==(const Image& o) const {
  return size_ == o.size_ && channels_ == o.channels_ && type_ == o.type_ && alpha_ == o.alpha_ &&
         std::equal(data_, data_ + bytes_, o.data_, o.data_ + o.bytes_);
}

Image Image::with_alpha() const {
  if (alpha_ >= 0 || channels_ > 3)
    throw InternalError("with_alpha on an image with alpha or 4 channels");
  Image out(size_, channels_ + 1, type_, channels_, Unfilled{});
  out.set_window(ox_, oy_, frame_size());
  const size_t sb = bytes_of(type_), pb = pixel_bytes(), ob = out.pixel_bytes();
  unsigned char one[4] = {};  // the opaque value's bytes in the sample type
  with_sample_type(type_, [&](auto t) { store<decltype(t)>(one, unit_of(type_)); });
  for (int64_t y = 0; y < size_.height; ++y) {
    const unsigned char* s = row(y);
    unsigned char* d = out.row(y);
    for (int64_t x = 0; x < size_.width; ++x, s += pb, d += ob) {
      std::memcpy(d, s, pb);
      std::memcpy(d + pb, one, sb);
    }
  }
  return out;
}

}  // namespace panoproj
