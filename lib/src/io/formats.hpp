#pragma once
// The image formats, one row each: how a file is recognised, what a file of its size can hold,
// its reader and writer, what it stores. Each codec file defines its formats' rows; the list below
// names them once. Whatever recognises, chooses, checks or lists formats asks this table, so a new
// format is its codec file, its line in the list, and its tests.
#include <climits>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "base/input_check.hpp"
#include "io/codec.hpp"

namespace panoproj {

struct ImageFormat {
  const char* name;   // OpenImageIO's name: what reports say and its readers take ("jpeg")
  const char* title;  // what messages say ("JPEG")
  std::vector<std::string_view> extensions;  // lower case with the dot, the usual one first
  // Whether a file's first bytes (up to 256 kB) are this format's; fills in what else they tell
  // (InputFile::arithmetic, bits_per_pixel).
  bool (*sniff)(const std::string& head, InputFile& file);
  // The most bytes of samples as stored (channels x bits a pixel) that a file of file.bytes can
  // hold in `window`, by its coding (compression: the header's, OpenImageIO's name): what a
  // decoding bomb's header is checked against.
  double (*most_stored)(const InputFile& file, Size window, const std::string& compression);
  int64_t max_side = INT_MAX;          // the writer's largest side
  PixelType deepest = PixelType::F32;  // U8: 8-bit samples only; U16: 8 or 16; F32: any
  bool floats_only = false;            // float samples only (Radiance HDR)
  bool float_channels = false;         // float samples in any number of channels (maps)
  bool embedded_metadata = false;      // EXIF, ICC and XMP blocks panoproj reads and writes itself
  bool holds_metadata = true;
  bool holds_alpha = true;      // false: an alpha channel is left out (JPEG, PNM, Radiance HDR)
  bool decodes_scaled = false;  // its reader decodes at 1/2, 1/4 and 1/8
  bool streams_blocks = false;  // its writer encodes parts as they are final (JpegBlockEncoder)
  bool web = false;             // browsers show it (tiles and views for viewers and trainers)
  // Built in: its reader and writer (and, where its samples can follow a header as they are, the
  // header, or "" where they cannot); null: OpenImageIO's, through the plugin.
  std::unique_ptr<Decoder> (*open)(const std::string& path, const InputFile& file) = nullptr;
  FileBytes (*encode)(const Image& image, const std::string& path, const WriteOptions& options,
                      const EmbeddedMetadata& meta) = nullptr;
  std::string (*raw_header)(const Image& image) = nullptr;

  bool built_in() const { return open != nullptr; }
  // The samples a file of this format gets for `wanted`: 8-bit only, floats as 16-bit integers,
  // floats only, or as is.
  PixelType stored_type(PixelType wanted) const;
};

// Every format, in the order files are sniffed and messages list them: X(Name) for the row
// kNameFormat that its codec file defines.
#define PANOPROJ_IMAGE_FORMATS(X) X(Jpeg) X(Png) X(Pnm) X(Tiff) X(OpenExr) X(Hdr)

#define PANOPROJ_FORMAT_ROW_(Name) extern const ImageFormat k##Name##Format;
PANOPROJ_IMAGE_FORMATS(PANOPROJ_FORMAT_ROW_)
#undef PANOPROJ_FORMAT_ROW_

// The rows of PANOPROJ_IMAGE_FORMATS, in its order.
const std::vector<const ImageFormat*>& image_formats();
// The row OpenImageIO calls `name`; InternalError if none.
const ImageFormat& format_named(std::string_view name);
// The format of an extension (".jpg", any case); null if none.
const ImageFormat* format_of_extension(std::string_view extension);
// The format a path's extension names; throws Error ("cannot write PATH: ...") listing them.
const ImageFormat& format_of_path(const std::string& path);
// The first format whose reader decodes scaled and that holds `type` (accuracy's files); throws
// Error naming those that do where none holds it.
const ImageFormat& scaled_format_for(PixelType type);
// The web format (ImageFormat::web) whose usual extension is `value` without its dot ("jpg");
// throws Error naming option_text(option, value) and those formats.
const ImageFormat& web_format(const std::string& value, std::string_view option);
// "JPEG, PNG, PPM/PGM, TIFF, OpenEXR or Radiance HDR"; ".jpg .jpeg .png ...".
std::string format_titles();
std::string format_extensions();

// Throws Error naming the path: missing (ErrorKind::Missing), not a regular file, empty, or none
// of the formats by its first bytes.
InputFile probe_input(const std::string& path);

// Throws Error unless a file of f.bytes can hold the `window` (of an image of `size`) to be
// decoded, channels x sample_bits bits a pixel stored with `compression` (its format's
// most_stored), and unless the decoded samples (decoded_bytes) fit the memory budget.
void check_plausible(const std::string& path, const InputFile& f, Size size, int channels,
                     int sample_bits, const std::string& compression, Size window,
                     uint64_t decoded_bytes, int64_t memory_limit);

// A coding's most expansion, decoded bytes per file byte (deflate 1032:1, LZW ~1500:1, PackBits
// 64:1, none 1:1, B44 16:1; others 10000:1), with 64 kB for headers: most_stored for the formats
// whose header names their coding.
double most_stored_by_compression(const InputFile& file, Size window,
                                  const std::string& compression);

}  // namespace panoproj
