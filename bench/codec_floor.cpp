// The codec floor of a conversion between JPEG files: libjpeg-turbo's decode of the input plus
// encode of the output, in process, one thread, libjpeg's defaults (islow DCT, fancy upsampling),
// quality and chroma subsampling as panoproj writes them. Prints the medians of --runs
// (milliseconds: decode, encode) and the encoded size, for bench_io.py.
//   codec_floor IN.jpg OUT.jpg [--quality Q] [--subsampling 420|422|444] [--runs N]
// (OUT.jpg is the conversion's output: decoded once, untimed, to have its pixels to encode.)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>
// clang-format off
#include <jpeglib.h>
// clang-format on

namespace {

struct Decoded {
  std::vector<unsigned char> pixels;
  unsigned width = 0, height = 0;
  int channels = 0;
};

// (No error manager of its own: a benchmark of panoproj's own files.)
Decoded decode(const char* path) {
  FILE* f = std::fopen(path, "rb");
  if (!f) std::exit(2);
  jpeg_decompress_struct c{};
  jpeg_error_mgr err{};
  c.err = jpeg_std_error(&err);
  jpeg_create_decompress(&c);
  jpeg_stdio_src(&c, f);
  jpeg_read_header(&c, TRUE);
  jpeg_start_decompress(&c);
  Decoded d{std::vector<unsigned char>(size_t{c.output_width} * c.output_height * c.output_components),
            c.output_width, c.output_height, c.output_components};
  while (c.output_scanline < c.output_height) {
    JSAMPROW row = d.pixels.data() + size_t{c.output_scanline} * d.width * d.channels;
    jpeg_read_scanlines(&c, &row, 1);
  }
  jpeg_finish_decompress(&c);
  jpeg_destroy_decompress(&c);
  std::fclose(f);
  return d;
}

size_t encode(const Decoded& d, int quality, int h, int v) {
  jpeg_compress_struct c{};
  jpeg_error_mgr err{};
  c.err = jpeg_std_error(&err);
  jpeg_create_compress(&c);
  unsigned char* out = nullptr;
  unsigned long size = 0;
  jpeg_mem_dest(&c, &out, &size);
  c.image_width = d.width, c.image_height = d.height, c.input_components = d.channels;
  c.in_color_space = d.channels == 1 ? JCS_GRAYSCALE : JCS_RGB;
  jpeg_set_defaults(&c);
  jpeg_set_quality(&c, quality, TRUE);
  if (d.channels == 3) {
    c.comp_info[0].h_samp_factor = h, c.comp_info[0].v_samp_factor = v;
    for (int k = 1; k < 3; ++k) c.comp_info[k].h_samp_factor = c.comp_info[k].v_samp_factor = 1;
  }
  jpeg_start_compress(&c, TRUE);
  while (c.next_scanline < c.image_height) {
    auto* row = const_cast<unsigned char*>(d.pixels.data() + size_t{c.next_scanline} * d.width * d.channels);
    jpeg_write_scanlines(&c, &row, 1);
  }
  jpeg_finish_compress(&c);
  jpeg_destroy_compress(&c);
  std::free(out);
  return size;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: codec_floor IN.jpg OUT.jpg [--quality Q] [--subsampling S] [--runs N]\n");
    return 2;
  }
  int quality = 95, runs = 11;
  std::string subsampling = "420";
  for (int i = 3; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--quality")) quality = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--subsampling")) subsampling = argv[i + 1];
    if (!std::strcmp(argv[i], "--runs")) runs = std::atoi(argv[i + 1]);
  }
  const int h = subsampling == "444" ? 1 : 2, v = subsampling == "420" ? 2 : 1;
  const Decoded output = decode(argv[2]);
  std::vector<double> decode_ms, encode_ms;
  size_t bytes = 0;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    const Decoded in = decode(argv[1]);
    const auto t1 = std::chrono::steady_clock::now();
    bytes = encode(output, quality, h, v);
    const auto t2 = std::chrono::steady_clock::now();
    decode_ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    encode_ms.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
  }
  std::printf("%.3f %.3f %zu\n", median(decode_ms), median(encode_ms), bytes);
}
