#include "io/npy.hpp"

#include <bit>
#include <cstring>

#include "panoproj/error.hpp"

namespace panoproj {

std::string npy_bytes(const Image& image) {
  static_assert(std::endian::native == std::endian::little, "'<f4' samples are written as stored");
  if (image.type() != PixelType::F32) throw InternalError(".npy output of a non-float32 image");
  // The header: a Python dict literal, padded with spaces and a newline so the samples start at
  // a multiple of 64 bytes (NumPy's format description, version 1.0).
  std::string dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (" +
                     std::to_string(image.height()) + ", " + std::to_string(image.width()) + ", " +
                     std::to_string(image.channels()) + "), }";
  const size_t fixed = 6 + 2 + 2;  // magic, version, header length
  dict.append(63 - (fixed + dict.size()) % 64, ' ');
  dict += '\n';
  std::string out("\x93NUMPY\x01\x00", 8);
  out += static_cast<char>(dict.size() & 0xFF);
  out += static_cast<char>(dict.size() >> 8);
  out += dict;
  const size_t row = static_cast<size_t>(image.width()) * static_cast<size_t>(image.channels()) * 4;
  out.reserve(out.size() + row * static_cast<size_t>(image.height()));
  for (int64_t y = 0; y < image.height(); ++y)
    out.append(reinterpret_cast<const char*>(image.row(y)), row);
  return out;
}

}  // namespace panoproj
