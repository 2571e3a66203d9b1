#pragma once
// Image files: JPEG (libjpeg-turbo), PNG (libpng) and binary PPM/PGM built in; TIFF 8/16-bit,
// OpenEXR half/float and Radiance HDR through OpenImageIO, loaded on first use (only these six,
// recognised by their magic bytes; written by the path's extension).
// Reading: only regular files, recognised by their magic bytes, whose header is plausible for the
// file's size and whose pixels fit the memory budget (limits.hpp; memory_limit 0: the machine's
// available memory), are decoded; anything else is a one-line Error.
// Writing cannot lose data: the file is encoded in memory, written to a temporary created
// exclusively beside the target (every write checked, synced), then renamed; on any failure the
// temporary is removed and an existing file is left as it was. An existing output (of any kind,
// a dangling link too) is replaced only with overwrite = true; the caller refuses outputs that
// are inputs.
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "panoproj/image.hpp"
#include "panoproj/projections/cubemap.hpp"

namespace panoproj {

// A file's attributes besides its pixels, by OpenImageIO's names ("Make", "Exif:FocalLength",
// "XResolution", "ICCProfile", "XMP" ...): integers, reals, text, real arrays, or bytes.
struct Attribute {
  using Value = std::variant<int64_t, double, std::string, std::vector<double>, std::vector<uint8_t>>;
  std::string name;
  Value value;
};
using Metadata = std::vector<Attribute>;

// A JPEG's or PNG's metadata blocks as stored: EXIF (the TIFF structure of a JPEG's APP1 after
// "Exif\0\0", a PNG's eXIf), the ICC profile (APP2 chunks, iCCP), the XMP packet (APP1, iTXt).
struct EmbeddedMetadata {
  std::string exif, icc, xmp;
  bool empty() const { return exif.empty() && icc.empty() && xmp.empty(); }
};

enum class ChromaSubsampling { S420, S422, S444 };
ChromaSubsampling parse_subsampling(std::string_view text);  // "420", "422", "444"

struct WriteOptions {
  bool overwrite = false;
  int quality = 95;  // JPEG, 1 to 100
  ChromaSubsampling subsampling = ChromaSubsampling::S420;  // JPEG: chroma at half width and height
  int threads = 0;  // JPEG encoders of a large image at once (in blocks, restart markers between): 0: all cores
  std::optional<PixelType> type;  // convert samples before writing; default: keep
  std::vector<std::string> channel_names;  // default: the format's (R, G, B, A)
  Metadata metadata;  // written where the format has a place for them, else dropped by it
  // Blocks carried as stored (a JPEG or PNG input's, read_embedded_metadata); EXIF is written with
  // Orientation 1 and the output's size, without thumbnail. Other formats get them as attributes.
  EmbeddedMetadata embedded;
  // An XMP packet for a JPEG or PNG output (photo_sphere.hpp), replacing embedded.xmp; other
  // formats: none.
  std::string xmp;
};

struct ImageInfo {
  Size size;
  int channels = 0;
  PixelType type = PixelType::U8;
  std::string format;     // jpeg, png, pnm, tiff, openexr, hdr
  bool scalable = false;  // decodes at 1/2, 1/4 and 1/8 (a JPEG's DCT scaling)
};

Image read_image(const std::string& path, int64_t memory_limit = 0);
// The file's attributes by OpenImageIO's names (its own "oiio:*" bookkeeping left out), through
// its plugin; without the plugin, a JPEG's or PNG's built-in set (ICCProfile, EXIF's common tags:
// exif.hpp, GPano: photo_sphere.hpp) and a PPM's none. Throws like read_image.
Metadata read_metadata(const std::string& path);
// A JPEG's or PNG's metadata blocks (others: none), without OpenImageIO.
EmbeddedMetadata read_embedded_metadata(const std::string& path);
// Blocks as attributes by OpenImageIO's names, without it: ICCProfile, EXIF's common tags
// (exif.hpp), the GPano fields (photo_sphere.hpp).
Metadata built_in_attributes(const EmbeddedMetadata& blocks);
// The image's size from its header only (no pixels decoded); throws like read_image.
Size read_image_size(const std::string& path);
ImageInfo read_image_info(const std::string& path);
// Reads at least the pixels [x0, x1) x [y0, y1) as a window of the file's frame (image.hpp), so
// that a damaged part outside the region is never needed: JPEG keeps exactly the region (it
// decodes one iMCU around it and skips the rows above without their inverse DCT; a progressive
// JPEG reads all its scans first), PNG and PPM keep the region's columns of rows y0..y1 (PNG
// decodes the rows above on the way; an interlaced PNG decodes whole), tiled TIFF and EXR the
// tiles it touches, other TIFF and EXR whole rows y0..y1. At scale 2, 4 or 8 (ImageInfo::scalable)
// the coordinates and the window are those of the frame decoded at 1/scale (size
// ceil(size / scale)). Before any pixel is decoded, the decoded part and `other_bytes` (a job's
// output and maps) are checked against the memory limit.
Image read_image_region(const std::string& path, int64_t x0, int64_t y0, int64_t x1, int64_t y1,
                        int64_t memory_limit = 0, uint64_t other_bytes = 0, int scale = 1);
void write_image(const Image& image, const std::string& path, const WriteOptions& options);
// What writing `image` to `path` (its format by the extension) with `options` loses, each a
// named warning: "alpha dropped: ...", "depth lowered: ..." (an options.type the format cannot
// hold), "samples clipped: ..." (float samples outside 0..1 or NaN into integers, counted),
// "metadata dropped: ...".
// `count_clipped`: false skips the pass over the samples (a batch that has said it once).
std::vector<std::string> write_warnings(const std::string& path, const Image& image,
                                        const WriteOptions& options, bool count_clipped = true);
// Throws unless `path` may be written: its folder exists (folder_made: or can be made, its nearest
// existing ancestor being a folder), and it is not a directory nor (without overwrite) an
// existing entry of any kind, a dangling link included.
void check_output_path(const std::string& path, bool overwrite, bool folder_made = false);
// Throws unless the format of `path` (by extension) can hold an image of `size` (JPEG: 65500 a
// side; others 2^31 - 1) and the options are valid (quality 1 to 100); write_image checks it too,
// this lets a job fail before its work.
void check_writable_size(const std::string& path, Size size);
void check_write_options(const WriteOptions& options);
// A text file (CSV, JSON ...) or any bytes, written like images.
void write_text(const std::string& text, const std::string& path, bool overwrite);
void write_bytes(std::string_view bytes, const std::string& path, bool overwrite);
// Throws unless the outputs of one job name different files (by device and inode where they
// exist, else by normalised path): each pair is {option or role, path}; empty paths are skipped.
void require_distinct_outputs(const std::vector<std::pair<std::string, std::string>>& outputs);
// A folder job's temporary folder (tiles, views), as a scheduler hands it to the processes that
// write into it: its path and identity. A process opens it by path without following a link and
// refuses a folder of another device or inode (one swapped in meanwhile).
struct StagedFolder {
  std::string path;
  uint64_t device = 0, inode = 0;
};
// Removes the temporaries of writes under way (and restores old files moved aside by a face set's
// commit) on SIGINT, SIGTERM and SIGHUP, then dies of the signal as before. For programs that own
// their signals (the panoproj command); Python keeps its own. Called again, it says on `fd` what a
// batch had done when its signal came (set_batch_progress).
void install_signal_cleanup(int fd = 2);
// What that signal's cleanup then says of a batch of `total` outputs of which `written` landed
// ("interrupted after 7 of 20; 7 written ..."; nothing for one output).
void set_batch_progress(int64_t written, int64_t total);

// Converts samples to another type (integers scale by their unit: 255 <-> 65535 <-> 1.0;
// floats are clamped to [0, 1] when going to integers, NaN and -inf to 0, +inf to the unit).
Image convert_pixels(const Image& image, PixelType type);

// Six cube faces as separate files: a pattern containing {face} (front, right, back, left,
// up, down), {index} (0..5) and/or {axis} (px nx py ny pz nz). In memory the faces form the 6x1
// strip. File k (the strip's slot k) holds the face and axis of slot k of the FaceOrder
// (projections/cubemap.hpp): {index} is k, {face} that face's name, {axis} its axis's.
bool is_face_pattern(std::string_view path);
std::string face_path(std::string_view pattern, int slot, const FaceOrder& order = kDefaultFaceOrder);
Image read_cube_faces(const std::string& pattern, int64_t memory_limit = 0, const FaceOrder& order = kDefaultFaceOrder);
// A GoPro MAX's two strips (one frame of each of its video streams, the first stream's first:
// gopro_max.hpp) as one frame, the first above the second; Error unless they match.
Image read_strip_pair(const std::string& first, const std::string& second,
                      int64_t memory_limit = 0);
// `strip` must be 6N x N. All six are written to temporary files first and renamed only when
// every one succeeded (old files restored if a rename fails).
void write_cube_faces(const Image& strip, const std::string& pattern, const WriteOptions& options,
                      const FaceOrder& order = kDefaultFaceOrder);

}  // namespace panoproj
