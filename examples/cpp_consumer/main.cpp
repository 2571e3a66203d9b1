// Reads a panorama (an EXR goes through the OpenImageIO plugin installed beside the library),
// renders a pinhole view of it and writes it: consumer IN OUT [SPEC].
#include <cstdio>
#include <string>

#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/io.hpp"
#include "panoproj/spec.hpp"
#include "panoproj/version.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: consumer IN OUT [SPEC]\n");
    return 2;
  }
  try {
    const panoproj::Image pano = panoproj::read_image(argv[1]);
    panoproj::ConvertOptions options;
    options.size = panoproj::Size{320, 240};
    const panoproj::Image view =
        panoproj::convert(pano, panoproj::parse_spec("equirect"),
                          panoproj::parse_spec(argc > 3 ? argv[3] : "pinhole:hfov=90"), options);
    panoproj::WriteOptions write;
    write.overwrite = true;
    panoproj::write_image(view, argv[2], write);
    std::printf("panoproj %s: %s (%lldx%lld) -> %s (%lldx%lld)\n", panoproj::version(), argv[1],
                static_cast<long long>(pano.width()), static_cast<long long>(pano.height()),
                argv[2], static_cast<long long>(view.width()),
                static_cast<long long>(view.height()));
  } catch (const panoproj::Error& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
  return 0;
}
