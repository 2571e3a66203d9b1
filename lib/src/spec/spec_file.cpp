// Specs from files, turned into spec text for parse_spec: a flat JSON object or a flat YAML mapping
// whose "projection" names the form and whose other keys are its spec keys (a lens calibration
// kept beside the photos); OCamCalib's calib_results.txt; a camera of Kalibr's camchain.yaml.
#include "spec/spec_file.hpp"

#include "spec/colmap_cameras.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <utility>
#include <vector>

#include "panoproj/error.hpp"
#include "base/input_check.hpp"
#include "base/text.hpp"

namespace panoproj {
namespace {

using Pairs = std::vector<std::pair<std::string, std::string>>;

constexpr std::string_view kSpace = " \t\r\n";

// {"key": value, ...} with string or number values; nothing nested.
Pairs parse_json(const std::string& text, const std::string& path) {
  Pairs out;
  size_t i = 0;
  auto fail = [&](const std::string& what) -> void {
    throw Error(path + ": " + what + " at character " + std::to_string(i + 1) +
                " (expected a flat JSON object of spec keys, e.g. {\"projection\": \"kannala-brandt\", \"fx\": 620.5})");
  };
  auto skip = [&] {
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
  };
  auto string = [&] {
    std::string s;
    if (text[i] != '"') fail("a string must start with \"");
    for (++i; i < text.size() && text[i] != '"'; ++i) {
      if (text[i] == '\\' && i + 1 < text.size()) ++i;
      s += text[i];
    }
    if (i >= text.size()) fail("an unterminated string");
    ++i;
    return s;
  };
  skip();
  if (i >= text.size() || text[i] != '{') fail("no object");
  ++i;
  skip();
  if (i < text.size() && text[i] == '}') return out;
  while (true) {
    skip();
    const std::string key = string();
    skip();
    if (i >= text.size() || text[i] != ':') fail("no ':' after \"" + key + "\"");
    ++i;
    skip();
    std::string value;
    if (i < text.size() && text[i] == '"') {
      value = string();
    } else {
      const size_t start = i;
      while (i < text.size() && text[i] != ',' && text[i] != '}' && !std::isspace(static_cast<unsigned char>(text[i]))) ++i;
      value = text.substr(start, i - start);
      if (value.empty() || value[0] == '{' || value[0] == '[') fail("the value of \"" + key + "\" is not a string or number");
    }
    out.emplace_back(key, value);
    skip();
    if (i < text.size() && text[i] == ',') {
      ++i;
      continue;
    }
    if (i < text.size() && text[i] == '}') {
      ++i;
      skip();
      if (i != text.size()) fail("text after the object");
      return out;
    }
    fail("no ',' or '}'");
  }
}

// key: value lines; '#' comments, blank lines and a leading "---" are skipped.
Pairs parse_yaml(const std::string& text, const std::string& path) {
  Pairs out;
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    line = trim(line, kSpace);
    if (line.empty() || line == "---") continue;
    const auto colon = line.find(':');
    if (colon == std::string::npos || line[0] == '-' || line[0] == ' ')
      throw Error(path + ": line " + std::to_string(n) + " is not 'key: value' (expected a flat YAML mapping of spec keys)");
    std::string value = trim(line.substr(colon + 1), kSpace);
    if (value.size() >= 2 && (value.front() == '"' || value.front() == '\'') && value.back() == value.front())
      value = value.substr(1, value.size() - 2);
    if (value.empty()) throw Error(path + ": line " + std::to_string(n) + " has no value (nested mappings are not supported)");
    out.emplace_back(trim(line.substr(0, colon), kSpace), value);
  }
  return out;
}

// A number token as written (kept to the digit), else Error naming the file and `what`.
std::string number_token(const std::string& t, const std::string& path, const std::string& what) {
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (t.empty() || end != t.c_str() + t.size() || !std::isfinite(v))
    throw Error(path + ": " + what + " holds '" + t + "' (expected a finite number)");
  return t;
}

std::vector<std::string> words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> w;
  for (std::string t; in >> t;) w.push_back(t);
  return w;
}

// OCamCalib's calib_results.txt: after '#' comments, the lines "n a0 .. a(n-1)" (pol), "m b0 ..
// b(m-1)" (invpol), "xc yc", "c d e" and, in newer files, "height width".
std::string ocamcalib_spec(const std::string& text, const std::string& path) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const std::string t = trim(line, kSpace);
    if (!t.empty() && t[0] != '#') rows.push_back(words(t));
  }
  const char* expected =
      " (expected OCamCalib's calib_results.txt: pol, invpol, centre, affine and size lines)";
  if (rows.size() < 4)
    throw Error(path + ": " + std::to_string(rows.size()) + " data lines" + expected);
  auto polynomial = [&](const std::vector<std::string>& row, const char* name) {
    char* end = nullptr;
    const long n = row.empty() ? -1 : std::strtol(row[0].c_str(), &end, 10);
    if (n < 1 || *end || static_cast<size_t>(n) + 1 != row.size())
      throw Error(path + ": the " + name + " line gives " + (row.empty() ? "nothing" : row[0]) +
                  " then " + std::to_string(row.empty() ? 0 : row.size() - 1) +
                  " coefficients (expected the count, then that many)");
    std::string v;
    for (size_t i = 1; i < row.size(); ++i)
      v += (i > 1 ? "/" : "") + number_token(row[i], path, name);
    return v;
  };
  const std::string pol = polynomial(rows[0], "pol"), invpol = polynomial(rows[1], "invpol");
  if (rows[2].size() != 2)
    throw Error(path + ": the centre line has " + std::to_string(rows[2].size()) + " values" +
                expected);
  if (rows[3].size() != 3)
    throw Error(path + ": the affine line has " + std::to_string(rows[3].size()) + " values" +
                expected);
  // The image size line (height, width), where the file has it.
  std::string size;
  if (rows.size() > 4) {
    if (rows[4].size() != 2)
      throw Error(path + ": the image size line has " + std::to_string(rows[4].size()) + " values" +
                  expected);
    size = ",width=" + number_token(rows[4][1], path, "width") +
           ",height=" + number_token(rows[4][0], path, "height");
  }
  return "ocamcalib:xc=" + number_token(rows[2][0], path, "xc") +
         ",yc=" + number_token(rows[2][1], path, "yc") + ",pol=" + pol + ",invpol=" + invpol +
         ",c=" + number_token(rows[3][0], path, "c") + ",d=" + number_token(rows[3][1], path, "d") +
         ",e=" + number_token(rows[3][2], path, "e") + size;
}

// Kalibr's camchain.yaml: cameras "camN:" at the margin, each with indented keys; the lists
// intrinsics and distortion_coeffs are "[a, b, ...]". `camera` names one ("" when the file holds
// one).
std::string kalibr_spec(const std::string& text, const std::string& path,
                        const std::string& camera) {
  std::vector<std::pair<std::string, Pairs>> cams;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    if (trim(line, kSpace).empty()) continue;
    const bool nested = line[0] == ' ' || line[0] == '\t';
    const std::string t = trim(line, kSpace);
    const auto colon = t.find(':');
    if (!nested) {
      if (colon == std::string::npos)
        throw Error(path + ": '" + t + "' is not 'camN:' (expected Kalibr's camchain.yaml)");
      cams.push_back({t.substr(0, colon), {}});
    } else if (!cams.empty() && colon != std::string::npos && t[0] != '-') {
      cams.back().second.emplace_back(trim(t.substr(0, colon), kSpace),
                                      trim(t.substr(colon + 1), kSpace));
    }
  }
  std::string names;
  for (const auto& c : cams) names += (names.empty() ? "" : ", ") + c.first;
  const std::pair<std::string, Pairs>* cam = nullptr;
  for (const auto& c : cams)
    if (c.first == camera || (camera.empty() && cams.size() == 1)) cam = &c;
  if (!cam)
    throw Error(path + (camera.empty()
                            ? ": holds cameras " + names + " (name one: @" + path + "#cam0)"
                            : ": no camera " + camera + " (it holds " + names + ")"));
  auto value = [&](const char* key) {
    for (const auto& [k, v] : cam->second)
      if (k == key) return v;
    throw Error(path + ": " + cam->first + " has no " + key + " (expected Kalibr's camchain.yaml)");
  };
  auto list = [&](const char* key) {
    std::string v = value(key);
    if (v.size() < 2 || v.front() != '[' || v.back() != ']')
      throw Error(path + ": " + cam->first + "'s " + key + " is not a [..] list");
    std::vector<std::string> out;
    std::istringstream items(v.substr(1, v.size() - 2));
    for (std::string item; std::getline(items, item, ',');)
      if (!trim(item, kSpace).empty())
        out.push_back(number_token(trim(item, kSpace), path, cam->first + "'s " + key));
    return out;
  };
  const std::string model = value("camera_model"), dist = value("distortion_model");
  const auto k = list("intrinsics"), d = list("distortion_coeffs");
  const std::string where = path + ": " + cam->first + "'s ";
  auto need = [&](const std::vector<std::string>& v, size_t n, const std::string& what) {
    if (v.size() != n)
      throw Error(where + what + " has " + std::to_string(v.size()) + " values (expected " +
                  std::to_string(n) + ")");
  };
  // Kalibr's intrinsics: [xi] [alpha] [beta] fu fv pu pv, per camera_model.
  const size_t law = model == "pinhole"                   ? 0
                     : model == "omni"                    ? 1
                     : (model == "ds" || model == "eucm") ? 2
                                                          : 99;
  if (law == 99)
    throw Error(where + "camera_model " + model + " (expected pinhole, omni, ds or eucm)");
  need(k, law + 4, "intrinsics (" + model + ")");
  // Kalibr's resolution [width, height], where given: the calibrated image's size.
  std::string size;
  for (const auto& [key, v] : cam->second)
    if (key == "resolution") {
      const auto r = list("resolution");
      need(r, 2, "resolution");
      size = ",width=" + r[0] + ",height=" + r[1];
    }
  const std::string K =
      "fx=" + k[law] + ",fy=" + k[law + 1] + ",cx=" + k[law + 2] + ",cy=" + k[law + 3] + size;
  const std::string combo = model + "-" + dist;
  if (combo == "pinhole-radtan") {
    need(d, 4, "distortion_coeffs (radtan)");
    return "brown-conrady:" + K + ",k1=" + d[0] + ",k2=" + d[1] + ",p1=" + d[2] + ",p2=" + d[3];
  }
  if (combo == "pinhole-equidistant") {
    need(d, 4, "distortion_coeffs (equidistant)");
    return "kannala-brandt:" + K + ",k1=" + d[0] + ",k2=" + d[1] + ",k3=" + d[2] + ",k4=" + d[3];
  }
  if (combo == "pinhole-fov") {
    need(d, 1, "distortion_coeffs (fov)");
    return "devernay-faugeras:" + K + ",omega=" + d[0];
  }
  if (combo == "pinhole-none") return "brown-conrady:" + K;
  if (combo == "omni-radtan") {
    need(d, 4, "distortion_coeffs (radtan)");
    return "omni-radtan:xi=" + k[0] + "," + K + ",k1=" + d[0] + ",k2=" + d[1] + ",p1=" + d[2] +
           ",p2=" + d[3];
  }
  if (combo == "omni-none") return "unified:xi=" + k[0] + "," + K;
  if (combo == "ds-none") return "double-sphere:xi=" + k[0] + ",alpha=" + k[1] + "," + K;
  if (combo == "eucm-none") return "extended-unified:alpha=" + k[0] + ",beta=" + k[1] + "," + K;
  throw Error(where + "camera_model " + model + " with distortion_model " + dist +
              " (expected pinhole with radtan, equidistant, fov or none; omni with radtan or none; "
              "ds or eucm with none)");
}

bool is_camchain(const std::string& text) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.find("camera_model:") != std::string::npos && (line[0] == ' ' || line[0] == '\t'))
      return true;
  return false;
}

}  // namespace

std::string spec_from_text(std::string text, const std::string& path, const std::string& camera) {
  if (is_colmap_cameras(text, path)) return colmap_camera_spec(text, path, camera);
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);  // a UTF-8 byte order mark
  if (is_camchain(text)) return kalibr_spec(text, path, camera);
  if (!camera.empty())
    throw Error(path + "#" + camera + ": #" + camera + " names a camera, but " + path +
                " is not Kalibr's camchain.yaml or COLMAP's cameras file");
  if (text.find("#polynomial coefficients for the DIRECT mapping function") != std::string::npos)
    return ocamcalib_spec(text, path);
  const std::string head = trim(text, kSpace);
  const Pairs pairs = !head.empty() && head[0] == '{' ? parse_json(head, path) : parse_yaml(text, path);
  std::string name, keys;
  for (size_t i = 0; i < pairs.size(); ++i) {
    const auto& [k, v] = pairs[i];
    for (size_t j = 0; j < i; ++j)
      if (pairs[j].first == k)
        throw Error(path + ": the key \"" + k + "\" is given twice (expected each key once)");
    if (k == "projection") {
      name = v;
    } else {
      if (v.find_first_of(",:") != std::string::npos)
        throw Error(path + ": the value of " + k + " holds ',' or ':' (expected a number or a word)");
      keys += "," + k + "=" + v;
    }
  }
  if (name.empty()) throw Error(path + ": no \"projection\" key (expected one naming the form, e.g. kannala-brandt)");
  // The name may carry keys of its own ("fisheye:fov=200").
  if (!keys.empty() && name.find(':') == std::string::npos) keys[0] = ':';
  return name + keys;
}

std::string spec_from_file(const std::string& path_text) {
  // "@camchain.yaml#cam1": a camera of a Kalibr file (a '#' that is part of an existing file's
  // name stays in it).
  std::string path = path_text, camera;
  if (const auto hash = path_text.rfind('#');
      hash != std::string::npos && !std::filesystem::exists(path_text)) {
    path = path_text.substr(0, hash);
    camera = path_text.substr(hash + 1);
  }
  // A spec file is a few lines: at most 1 MiB is read, 256 MiB of COLMAP's cameras (a camera
  // per image); read_head refuses directories, FIFOs and devices before reading.
  const bool cameras = is_colmap_cameras("", path);
  const size_t most = size_t{1} << (cameras ? 28 : 20);
  std::string text = read_head(path, most + 1, "the spec file", "a JSON or YAML file after @");
  if (text.size() > most)
    throw Error(path + (cameras ? " is over 256 MiB (expected COLMAP's cameras file)"
                                : " is over 1 MiB (expected a small JSON or YAML spec file)"));
  return spec_from_text(std::move(text), path, camera);
}

}  // namespace panoproj
