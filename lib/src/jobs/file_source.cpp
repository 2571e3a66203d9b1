#include "jobs/file_source.hpp"

#include <cctype>
#include <filesystem>
#include <sstream>

#include "panoproj/error.hpp"

namespace panoproj {

bool gopro_max_video(const std::string& input, const std::optional<std::string>& from) {
  if (from) return parse_spec(*from).kind() == Kind::GoProMax;
  std::string ext = std::filesystem::path(input).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".360";
}

ProjectionSpec infer_source_spec(const std::optional<std::string>& from, const std::string& input,
                                 Size size, const std::optional<PhotoSphere>& photo_sphere) {
  if (from) return parse_spec(*from);
  if (is_face_pattern(input)) return parse_spec("cubemap:layout=files");
  if (photo_sphere) return parse_spec(photo_sphere_spec(*photo_sphere, size));
  if (size.width == 2 * size.height) return parse_spec("equirect");
  throw Error("cannot tell the projection of " + input + " (" + std::to_string(size.width) + "x" +
              std::to_string(size.height) + " is not a 2:1 equirect): give " + option_text("from") +
              " SPEC");
}

std::string level_by_pose(ConversionGeometry& geometry, const std::optional<PhotoSphere>& ps,
                          std::string from_text) {
  if (!ps || (ps->pose_pitch == 0 && ps->pose_roll == 0)) return from_text;
  geometry.rotation = photo_sphere_pose(*ps).transpose() * geometry.rotation;
  std::ostringstream o;
  o << from_text << ", levelled by its Photo Sphere pose: pitch " << ps->pose_pitch << ", roll "
    << ps->pose_roll;
  return o.str();
}

FileSource open_file_source(const std::string& input, const std::optional<std::string>& from,
                            const ConvertOptions& options, const char* what) {
  const ImageInfo info = read_image_info(input);
  return source_of(info, input, from, from ? std::nullopt : read_photo_sphere(input), options,
                   what);
}

FileSource source_of(const ImageInfo& info, const std::string& input,
                     const std::optional<std::string>& from, const std::optional<PhotoSphere>& ps,
                     const ConvertOptions& options, const char* what) {
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
