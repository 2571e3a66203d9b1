// The codec floor of a conversion between JPEG files: in-process libjpeg-turbo decode of the input
// plus encode of the output (panoproj's own codecs, one thread), same quality and subsampling as
// panoproj writes. Prints the median of --runs (milliseconds) for bench_io.py.
//   codec_floor IN.jpg OUT.jpg [--quality Q] [--subsampling 420|422|444] [--runs N]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "panoproj/io.hpp"
#include "io/codec.hpp"

using namespace panoproj;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: codec_floor IN.jpg OUT.jpg [--quality Q] [--subsampling S] [--runs N]\n");
    return 2;
  }
  WriteOptions w;
  int runs = 11;
  for (int i = 3; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--quality")) w.quality = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--subsampling")) w.subsampling = parse_subsampling(argv[i + 1]);
    if (!std::strcmp(argv[i], "--runs")) runs = std::atoi(argv[i + 1]);
  }
  const Image output = read_image(argv[2]);  // what is encoded: the conversion's result
  std::vector<double> decode, encode;
  size_t bytes = 0;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    const Image in = read_image(argv[1]);
    const auto t1 = std::chrono::steady_clock::now();
    bytes = encode_jpeg(output, "floor.jpg", w, {}).size();
    const auto t2 = std::chrono::steady_clock::now();
    decode.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    encode.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  std::printf("%.3f %.3f %zu\n", median(decode), median(encode), bytes);
}
