#include "io/video_formats.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

#include "panoproj/error.hpp"

namespace panoproj {

const std::vector<VideoContainer>& video_containers() {
  static const std::vector<VideoContainer> rows = {
      {"mp4", {".mp4", ".m4v"}, "h264"}, {"mov", {".mov"}, "h264"},
      {"mkv", {".mkv"}, "h264"},         {"webm", {".webm"}, "vp9"},
      {"avi", {".avi"}, "h264"},         {"mpegts", {".ts", ".mts", ".m2ts"}, "h264"},
  };
  return rows;
}

const VideoContainer* video_container_of(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  for (const VideoContainer& c : video_containers())
    for (std::string_view e : c.extensions)
      if (e == ext) return &c;
  return nullptr;
}

bool is_video_file(const std::string& path) {
  if (video_container_of(path)) return true;
  // (Only a regular file is sniffed: a FIFO or device is the image path's to refuse, unread.)
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  std::ifstream f(path, std::ios::binary);
  std::string head(512, '\0');
  f.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(std::max<std::streamsize>(f.gcount(), 0)));
  return sniffs_as_video(head);
}

bool sniffs_as_video(const std::string& head) {
  if (head.size() >= 12 && head.compare(4, 4, "ftyp") == 0) {
    // (HEIF and AVIF images are ISO BMFF too: their brands are not video's.)
    const std::string brand = head.substr(8, 4);
    for (const char* image : {"heic", "heix", "mif1", "msf1", "avif", "avis", "heim", "heis"})
      if (brand == image) return false;
    return true;
  }
  if (head.size() >= 4 && head.compare(0, 4, "\x1a\x45\xdf\xa3") == 0)
    return true;  // Matroska, WebM
  if (head.size() >= 12 && head.compare(0, 4, "RIFF") == 0 && head.compare(8, 3, "AVI") == 0)
    return true;
  return head.size() >= 377 && head[0] == 0x47 && head[188] == 0x47 &&
         head[376] == 0x47;  // MPEG-TS
}

const std::vector<VideoCodec>& video_codecs() {
  static const std::vector<VideoCodec> rows = {
      {"h264", "libx264"},   {"hevc", "libx265"}, {"av1", "libsvtav1"},
      {"vp9", "libvpx-vp9"}, {"ffv1", "ffv1"},    {"prores", "prores_ks"},
  };
  return rows;
}

const VideoCodec& video_codec(const std::string& name) {
  std::string names;
  for (const VideoCodec& c : video_codecs()) {
    if (name == c.name) return c;
    names += (names.empty() ? "" : ", ") + std::string(c.name);
  }
  throw Error("--codec " + name + " is not one of " + names);
}

}  // namespace panoproj
