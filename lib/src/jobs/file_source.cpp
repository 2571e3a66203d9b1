#include "jobs/file_source.hpp"

#include "panoproj/jobs.hpp"
#include "panoproj/photo_sphere.hpp"

namespace panoproj {

FileSource open_file_source(const std::string& input, const std::optional<std::string>& from, const ConvertOptions& options,
                            const char* what) {
  const ImageInfo info = read_image_info(input);
  const auto ps = from ? std::nullopt : read_photo_sphere(input);
  const ProjectionSpec spec = infer_source_spec(from, input, info.size, ps);
  ConvertOptions o = options;
  o.size = Size{1, 1};  // (the target is replaced per part)
  ConversionGeometry g = make_geometry(info.size, spec, parse_spec("pinhole:hfov=90"), o);
  require_mono(g, what);
  std::string from_text = level_by_pose(g, ps, spec.str());
  const bool partial = !shows_whole_sphere(g.source);
  return FileSource{info, std::move(g), std::move(from_text), partial};
}

}  // namespace panoproj
