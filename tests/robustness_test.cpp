// The file boundary under faults and hostile input, at the library's level (the command and the
// Python module have theirs in python/tests/test_robustness.py). Each case asserts the error's
// kind and one line naming the file, that nothing was left behind and that an old file is intact.
//   - Write faults: RLIMIT_FSIZE makes the kernel fail every write past a byte offset (EFBIG, with
//     SIGXFSZ ignored), whichever library or stream issues it; each format is cut at several
//     offsets, and the message must show that the fault fired (the byte it stopped at).
//   - Hostile and odd inputs: headers declaring more than their file holds, non-regular files,
//     empty files, unknown formats.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "panoproj/error.hpp"
#include "panoproj/io.hpp"
#include "panoproj/limits.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

namespace fs = std::filesystem;

std::string bytes_of_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// Writes in its scope fail past `bytes` bytes of any one file (EFBIG).
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &saved_);
    old_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    const rlimit r{bytes, saved_.rlim_max};
    setrlimit(RLIMIT_FSIZE, &r);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, old_handler_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

 private:
  rlimit saved_{};
  void (*old_handler_)(int) = nullptr;
};

class Robustness : public test::TempDirTest {
 protected:
  // The folder's entries other than `keep` (temporaries left behind, partial outputs).
  std::vector<std::string> others(const std::vector<std::string>& keep) const {
    std::vector<std::string> v;
    for (const auto& e : fs::directory_iterator(dir_)) {
      const std::string n = e.path().filename().string();
      if (std::find(keep.begin(), keep.end(), n) == keep.end()) v.push_back(n);
    }
    return v;
  }
};

// ---- write faults: every output format, cut at several byte offsets --------------------------

struct WriteCase {
  std::string name, file;  // file: an output name, "{face}" for a set of six
  double cut;              // where writes start failing, as a share of the file's size
};

std::string case_name(const ::testing::TestParamInfo<WriteCase>& i) { return i.param.name; }
void PrintTo(const WriteCase& c, std::ostream* os) { *os << c.name; }

class WriteFault : public Robustness, public ::testing::WithParamInterface<WriteCase> {};

TEST_P(WriteFault, FailsWithTheOutputsNameAndLeavesTheOldFileIntact) {
  const WriteCase& c = GetParam();
  const bool faces = is_face_pattern(c.file), text = c.file.ends_with(".csv");
  // (A JPEG of 2^20 pixels and more is encoded in blocks and joined.)
  const Size size = faces ? Size{6 * 24, 24} : c.file == "blocks.jpg" ? Size{2100, 1000} : Size{160, 80};
  const Image image = test::pattern(size, 3, PixelType::U8, -1);
  const std::string target = path(c.file);
  std::vector<std::string> names;
  for (int f = 0; f < (faces ? 6 : 1); ++f) names.push_back(faces ? face_path(target, f) : target);
  WriteOptions w;
  w.overwrite = true;
  std::string csv(5000, 'x');
  auto write = [&] {
    if (text) write_text(csv, target, true);
    else if (faces) write_cube_faces(image, target, w);
    else write_image(image, target, w);
  };
  // The old files, and the size of a full new one.
  for (const auto& n : names) std::ofstream(n, std::ios::binary) << "old " << n;
  write();
  const auto full = fs::file_size(names.back());
  for (const auto& n : names) std::ofstream(n, std::ios::binary | std::ios::trunc) << "old " << n;
  const auto limit = static_cast<rlim_t>(static_cast<double>(full) * c.cut);
  std::string message;
  ErrorKind kind = ErrorKind::Value;
  {
    FileSizeLimit cap(limit);
    try {
      write();
    } catch (const Error& e) {
      message = e.what();
      kind = e.kind();
    }
  }
  ASSERT_FALSE(message.empty()) << "the write succeeded under a " << limit << "-byte limit";
  EXPECT_EQ(kind, ErrorKind::File);
  EXPECT_EQ(message.find('\n'), std::string::npos);
  // The fault fired where it was set: the message names an output (not a temporary) and says
  // at which byte of how many it stopped, and why.
  EXPECT_NE(message.find("cannot write " + (faces ? dir_.string() : target)), std::string::npos) << message;
  EXPECT_EQ(message.find(".panoproj-"), std::string::npos) << message;
  EXPECT_NE(message.find("writing byte " + std::to_string(limit) + " of"), std::string::npos) << message;
  EXPECT_NE(message.find("File too large"), std::string::npos) << message;
  for (const auto& n : names) EXPECT_EQ(bytes_of_file(n), "old " + n);
  std::vector<std::string> keep;
  for (const auto& n : names) keep.push_back(fs::path(n).filename().string());
  EXPECT_TRUE(others(keep).empty()) << others(keep).front();
}

std::vector<WriteCase> write_cases() {
  std::vector<WriteCase> v;
  for (const std::string ext : {"jpg", "png", "ppm", "tif", "exr", "hdr", "csv"})
    for (const auto& [cut_name, cut] : {std::pair{"at0", 0.0}, {"at1byte", 1e-9}, {"at10pct", 0.1}, {"at50pct", 0.5},
                                        {"at99pct", 0.99}})
      v.push_back({ext + "_" + cut_name, "out." + ext, cut});
  for (const auto& [cut_name, cut] : {std::pair{"at1byte", 1e-9}, {"at50pct", 0.5}, {"at99pct", 0.99}})
    v.push_back({std::string("jpg_blocks_") + cut_name, "blocks.jpg", cut});
  // A face set: the limit cuts the sixth face (each face is about a sixth of the set).
  for (const auto& [cut_name, cut] : {std::pair{"at0", 0.0}, {"at50pct", 0.5}, {"at99pct", 0.99}})
    v.push_back({std::string("faces_png_") + cut_name, "{face}.png", cut});
  return v;
}

INSTANTIATE_TEST_SUITE_P(Formats, WriteFault, ::testing::ValuesIn(write_cases()), case_name);

// ---- outputs that must not be written ---------------------------------------------------------

TEST_F(Robustness, ExistingOutputsOfAnyKindNeedOverwrite) {
  const Image image = test::pattern({16, 8}, 3, PixelType::U8, -1);
  fs::create_symlink(path("nowhere.png"), path("dangling.png"));
  std::ofstream(path("plain.png")) << "old";
  for (const char* name : {"dangling.png", "plain.png"}) {
    try {
      write_image(image, path(name), {});
      FAIL() << name;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::Exists) << e.what();
      EXPECT_NE(std::string(e.what()).find("pass --overwrite"), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(fs::is_symlink(path("dangling.png")));
  EXPECT_FALSE(fs::exists(path("nowhere.png")));
  // With overwrite the link itself is replaced, never the file it points to.
  WriteOptions w;
  w.overwrite = true;
  std::ofstream(path("target.png")) << "precious";
  fs::create_symlink(path("target.png"), path("link.png"));
  write_image(image, path("link.png"), w);
  EXPECT_FALSE(fs::is_symlink(path("link.png")));
  EXPECT_EQ(bytes_of_file(path("target.png")), "precious");
  // A directory is never replaced.
  fs::create_directory(path("dir.png"));
  try {
    write_image(image, path("dir.png"), w);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
  }
}

TEST_F(Robustness, AFaceSetWithOneUnwritableFaceWritesNone) {
  // left.png is a directory: nothing of the set is replaced, nothing is left behind.
  const Image strip = test::pattern({6 * 8, 8}, 3, PixelType::U8, -1);
  for (int f = 0; f < 6; ++f) std::ofstream(face_path(path("{face}.png"), f)) << "old";
  fs::remove(path("left.png"));
  fs::create_directory(path("left.png"));
  WriteOptions w;
  w.overwrite = true;
  EXPECT_THROW(write_cube_faces(strip, path("{face}.png"), w), Error);
  for (int f = 0; f < 6; ++f) {
    if (f != 3) {
      EXPECT_EQ(bytes_of_file(face_path(path("{face}.png"), f)), "old") << f;
    }
  }
  EXPECT_EQ(others({"front.png", "right.png", "back.png", "left.png", "up.png", "down.png"}).size(), 0u);
}

TEST_F(Robustness, LongOutputNamesFitTheirTemporaries) {
  // A 250-byte name: the temporary's own name has a fixed length, so it stays within NAME_MAX.
  const std::string name = std::string(246, 'n') + ".png";
  write_image(test::pattern({8, 8}, 3, PixelType::U8, -1), path(name), {});
  EXPECT_TRUE(fs::exists(path(name)));
  EXPECT_TRUE(others({name}).empty());
}

TEST_F(Robustness, FaceSetsMustBeStripsOfSquareFaces) {
  try {
    write_cube_faces(Image({300, 256}, 3, PixelType::U8), path("{face}.png"), {});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("300x256"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(others({}).empty());
}

TEST_F(Robustness, SizesAFormatCannotHoldAreRefusedBeforeEncoding) {
  // libjpeg would end the process beyond 65500 a side.
  try {
    write_image(Image({65501, 1}, 1, PixelType::U8), path("wide.jpg"), {});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("65501x1 pixels, over the JPEG limit of 65500"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(others({}).empty());
}

// ---- hostile and odd inputs -------------------------------------------------------------------

struct InputCase {
  std::string name, bytes, expected;
};

class HostileInput : public Robustness, public ::testing::WithParamInterface<InputCase> {};

TEST_P(HostileInput, IsRefusedInOneLineBeforeDecoding) {
  const InputCase& c = GetParam();
  const std::string file = path("in");
  std::string bytes = c.bytes;
  if (bytes == "patched-jpeg") {
    // A real JPEG whose frame header (SOF0) is patched to declare 65500 x 32750 pixels.
    write_image(test::pattern({256, 128}, 3, PixelType::U8, -1), path("real.jpg"), {});
    bytes = bytes_of_file(path("real.jpg"));
    fs::remove(path("real.jpg"));
    const size_t sof = bytes.find("\xFF\xC0");
    ASSERT_NE(sof, std::string::npos);
    bytes.replace(sof + 5, 4, "\x7F\xEE\xFF\xDC");
  }
  std::ofstream(file, std::ios::binary) << bytes;
  for (int region = 0; region < 2; ++region) {
    try {
      if (region) (void)read_image_region(file, 0, 0, 8, 8);
      else (void)read_image(file);
      FAIL() << "read";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(file), std::string::npos) << m;
      // (A region's first rows may be plausible for the file: then its decoder says what is wrong.)
      if (!region) {
        EXPECT_NE(m.find(c.expected), std::string::npos) << m;
      }
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
      EXPECT_LE(m.size(), 400u) << m;
    }
  }
}

std::string be32(uint32_t v) {
  return {static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8), static_cast<char>(v)};
}

std::vector<InputCase> hostile_cases() {
  // A PNG whose IHDR declares 1000000 x 1000000 RGB.
  std::string png = std::string("\x89PNG\r\n\x1a\n", 8) + be32(13) + "IHDR" + be32(1000000) + be32(1000000) +
                    std::string("\x08\x02\x00\x00\x00", 5) + be32(0) + std::string(200, '\0');
  // A TIFF (little-endian) of one IFD: 100000 x 40000, 8-bit RGB, uncompressed, one strip.
  auto le16 = [](uint16_t v) { return std::string{static_cast<char>(v & 0xFF), static_cast<char>(v >> 8)}; };
  auto le32 = [](uint32_t v) {
    return std::string{static_cast<char>(v & 0xFF), static_cast<char>((v >> 8) & 0xFF), static_cast<char>((v >> 16) & 0xFF),
                       static_cast<char>(v >> 24)};
  };
  std::string tiff = "II*" + std::string(1, '\0') + le32(8);
  const std::vector<std::array<uint32_t, 3>> tags = {{256, 4, 100000}, {257, 4, 40000}, {258, 3, 8},  {259, 3, 1},
                                                     {262, 3, 2},      {273, 4, 200},   {277, 3, 3},  {278, 4, 40000},
                                                     {279, 4, 12000000}};
  tiff += le16(static_cast<uint16_t>(tags.size()));
  for (const auto& [tag, type, value] : tags)
    tiff += le16(static_cast<uint16_t>(tag)) + le16(static_cast<uint16_t>(type)) + le32(1) +
            (type == 3 ? le16(static_cast<uint16_t>(value)) + le16(0) : le32(value));
  tiff += le32(0) + std::string(800, '\0');
  const std::string hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000 +X 100000\n" + std::string(100, '\x01');
  return {
      {"jpeg_patched_to_65500x32750", "patched-jpeg", "too few to hold them"},
      {"png_1000000_squared", png, "cannot read"},
      {"tiff_100000x40000_in_1kB", tiff, "too few to hold them"},
      {"hdr_100000_squared", hdr, "too few to hold them"},
      {"empty", "", "the file is empty"},
      {"garbage", std::string(3000, 'x'), "not a JPEG, PNG, PPM/PGM, TIFF, OpenEXR or Radiance HDR image"},
      {"png_signature_only", std::string("\x89PNG\r\n\x1a\n", 8), "cannot read"},
      {"jpeg_soi_only", std::string("\xFF\xD8\xFF", 3), "cannot read"},
      {"tiff_header_only", std::string("II*\0\x08\0\0\0", 8), "cannot read"},
      {"exr_magic_only", std::string("\x76\x2f\x31\x01", 4), "cannot read"},
      {"ppm_2147483647_squared", "P6\n2147483647 2147483647\n255\n" + std::string(100, 'x'), "too few to hold them"},
      {"ppm_maxval_0", "P6\n4 4\n0\n" + std::string(48, 'x'), "maxval 0"},
      {"ppm_header_only", std::string("P5\n"), "damaged PPM/PGM header"},
      {"ppm_width_over_2_31", "P5\n99999999999 1\n255\n" + std::string(10, 'x'), "over 2^31"},
  };
}

std::string input_name(const ::testing::TestParamInfo<InputCase>& i) { return i.param.name; }
void PrintTo(const InputCase& c, std::ostream* os) { *os << c.name; }

INSTANTIATE_TEST_SUITE_P(Files, HostileInput, ::testing::ValuesIn(hostile_cases()), input_name);

TEST_F(Robustness, NonRegularInputsAreRefusedWithoutOpeningThem) {
  ASSERT_EQ(::mkfifo(path("fifo").c_str(), 0600), 0);
  fs::create_directory(path("dir"));
  fs::create_symlink("/dev/zero", path("zero.jpg"));
  for (const auto& [name, kind] : {std::pair{path("fifo"), "a FIFO"}, {path("dir"), "a directory"},
                                   {std::string("/dev/zero"), "a device"}, {path("zero.jpg"), "a device"}}) {
    for (int what = 0; what < 3; ++what) {
      try {
        if (what == 0) (void)read_image(name);
        if (what == 1) (void)read_image_size(name);
        if (what == 2) (void)read_metadata(name);
        FAIL() << name;
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(kind), std::string::npos) << e.what();
        EXPECT_EQ(e.kind(), ErrorKind::File);
      }
    }
  }
  try {
    (void)read_image(path("missing.png"));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Missing);
  }
}

TEST_F(Robustness, TheMemoryBudgetRefusesPlausibleFilesTooBigForIt) {
  // A real 2000x1000 PNG is fine; under a 1 MB limit it is refused with its size and the bytes.
  write_image(test::pattern({2000, 1000}, 3, PixelType::U8, -1), path("big.png"), {});
  EXPECT_EQ(read_image(path("big.png")).width(), 2000);
  try {
    (void)read_image(path("big.png"), 1000000);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Memory);
    EXPECT_NE(std::string(e.what()).find("2000x1000"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("needs 6.0 MB, over the memory limit of 1.0 MB"), std::string::npos) << e.what();
  }
}

TEST_F(Robustness, LegitimateExtremeFilesStillPass) {
  // The plausibility rules must not refuse what the encoders make of flat images at their best
  // compression: a black 8192x4096 PNG (deflate near its 1032:1 bound), and a flat JPEG.
  const Image black({8192, 4096}, 3, PixelType::U8);
  write_image(black, path("black.png"), {});
  write_image(black, path("black.jpg"), {});
  const Image grey1({16384, 8}, 1, PixelType::U8);
  write_image(grey1, path("grey.tif"), {});
  for (const char* name : {"black.png", "black.jpg", "grey.tif"}) {
    SCOPED_TRACE(name);
    EXPECT_NO_THROW((void)read_image(path(name)));
  }
  EXPECT_LT(fs::file_size(path("black.png")) * 900, black.byte_size());  // near the bound indeed
}

TEST(Limits, ByteCountsSaturateInsteadOfOverflowing) {
  EXPECT_EQ(image_bytes({4294967296, 4294967296}, 3, 1), UINT64_MAX);
  EXPECT_EQ(image_bytes({2000, 1000}, 3, 2), 12000000u);
  EXPECT_EQ(add_bytes(UINT64_MAX - 1, 5), UINT64_MAX);
  EXPECT_EQ(parse_memory_limit("4G"), 4000000000);
  EXPECT_EQ(parse_memory_limit("512MB"), 512000000);
  EXPECT_THROW(parse_memory_limit("lots"), Error);
  EXPECT_THROW(parse_memory_limit("1e300"), Error);
  EXPECT_THROW(parse_memory_limit("-4G"), Error);
}

TEST(Limits, NanAndInfinitySamplesBecomeDefinedIntegers) {
  Image f({4, 1}, 1, PixelType::F32);
  const float v[4] = {std::nanf(""), INFINITY, -INFINITY, 0.5f};
  std::memcpy(f.data(), v, sizeof v);
  const Image u = convert_pixels(f, PixelType::U8);
  EXPECT_EQ(u.data()[0], 0);
  EXPECT_EQ(u.data()[1], 255);
  EXPECT_EQ(u.data()[2], 0);
  EXPECT_EQ(u.data()[3], 128);
}

}  // namespace
}  // namespace panoproj
