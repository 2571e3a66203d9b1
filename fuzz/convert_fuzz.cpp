// Fuzzes whole conversions of small images: the input's first line is the source spec, its second
// the target spec; then one byte each picks the kernel, antialiasing, engine, channels, sample
// type, size and rotation; the rest are the source's pixels (repeated to fill it). Any spec text
// the parser accepts must convert without a crash, a sanitizer report or an exception other than
// panoproj::Error (photometric keys too: each source pixel corrected). Sizes stay at most 48x48 and
// the memory limit at 64 MB, so runs are quick.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "panoproj/options.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/spec.hpp"

using namespace panoproj;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const size_t a = text.find('\n');
  const size_t b = a == std::string::npos ? a : text.find('\n', a + 1);
  if (b == std::string::npos || b + 10 > text.size()) return 0;  // two lines, then 9 option bytes
  const auto* p = data + b + 1;
  static const Interp kInterp[] = {Interp::Nearest, Interp::Bilinear, Interp::Bicubic, Interp::Lanczos3,
                                   Interp::BicubicDering, Interp::Lanczos3Dering};
  static const Engine kEngine[] = {Engine::Simd, Engine::Scalar, Engine::Reference};
  static const PixelType kType[] = {PixelType::U8, PixelType::U16, PixelType::F16, PixelType::F32};
  ConvertOptions o;
  o.interp = kInterp[p[0] % 6];
  static const char* const kAntialias[] = {"off", "auto", "mip", "2", "3"};
  o.antialias = parse_antialias(kAntialias[p[1] % 5]);
  o.engine = kEngine[p[2] % 3];
  const int channels = 1 + p[3] % 4;
  const PixelType type = kType[p[4] % 4];
  o.size = Size{1 + p[5] % 48, 1 + p[6] % 48};
  o.yaw = p[7] * 1.5, o.pitch = p[8] % 181 - 90.0;
  o.threads = 1;
  o.memory_limit = int64_t{64} << 20;
  o.add_alpha = p[3] & 0x80;
  o.edges.soft = o.add_alpha;
  // (A flat field is a file: read by the reader's fuzz target, and a path could block the run.)
  if (text.substr(0, b).find("flat_field") != std::string::npos) return 0;
  try {
    const ProjectionSpec from = parse_spec(text.substr(0, a)), to = parse_spec(text.substr(a + 1, b - a - 1));
    // The source at the size its spec wants when it has one (a cubemap's 6:1), else 32x16.
    Size src{32, 16};
    if (from.kind() == Kind::Cubemap) src = {96, 16};
    Image in(src, channels, type, channels == 2 || channels == 4 ? channels - 1 : -1);
    const size_t pixels = b + 10 < size ? size - (b + 10) : 0;
    for (size_t i = 0; pixels && i < in.byte_size(); ++i) in.data()[i] = data[b + 10 + i % pixels];
    (void)convert(in, from, to, o);
  } catch (const Error&) {
  }
  return 0;
}
