#pragma once
// Google's Photo Sphere XMP (the GPano namespace, developers.google.com/streetview/spherical-
// metadata): how a (possibly cropped) equirect sits in its full panorama. OpenImageIO does not
// decode this namespace, so panoproj reads and writes the XMP packet of JPEG files (an APP1
// segment "http://ns.adobe.com/xap/1.0/") and PNG files (an iTXt chunk "XML:com.adobe.xmp")
// itself.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "panoproj/io.hpp"
#include "panoproj/projection.hpp"

namespace panoproj {

struct PhotoSphere {
  std::string projection_type = "equirectangular";
  int64_t full_width = 0, full_height = 0;  // FullPanoWidthPixels, FullPanoHeightPixels
  int64_t crop_width = 0, crop_height = 0;  // CroppedAreaImageWidthPixels, ...HeightPixels
  int64_t crop_left = 0, crop_top = 0;      // CroppedAreaLeftPixels, CroppedAreaTopPixels
  // PosePitchDegrees (the image centre's elevation above the horizon) and PoseRollDegrees (the
  // horizon turns counter-clockwise in the image as it grows): how the camera was tilted.
  // (PoseHeadingDegrees, the centre's compass heading, is not read: it turns nothing.)
  double pose_pitch = 0, pose_roll = 0;
  // A stereo frame's layout (GPano has none): written as GSpherical:StereoMode (Google's Spherical
  // Video RFC, namespace http://ns.google.com/videos/1.0/spherical/): "top-bottom" or
  // "left-right"; "" for mono. The GPano fields then describe one eye.
  std::string stereo_mode;
};

// The camera's tilt from its pose: camera ray -> level ray, rotation_from_ypr(0, pitch, roll)
// (GPano's roll is rotation.hpp's: the camera turned clockwise, the picture counter-clockwise).
// A conversion levels the panorama with its transpose before the view's own rotation.
Eigen::Matrix3d photo_sphere_pose(const PhotoSphere& ps);

// The GPano fields of a JPEG's or PNG's XMP (and GSpherical:StereoMode); none if the file has no
// XMP packet with the equirect's fields (other files: none). Throws panoproj::Error if the file
// cannot be read or a field is not of its type.
std::optional<PhotoSphere> read_photo_sphere(const std::string& path);

// The GPano fields of an XMP packet as attributes "GPano:Name", by the spec's types: Integer and
// Boolean (True: 1) fields as integers, Real as floats, Text as strings; a field whose text is not
// of its type is left out.
Metadata photo_sphere_attributes(const std::string& xmp);

// The spec of an image of `size` carrying `ps`: its crop as a partial equirect (the crop may be
// stored scaled; its fields are in full-panorama pixels); a stereo frame's (stereo=tb|sbs) fields
// describe one eye. Throws panoproj::Error naming the bad
// field for a projection type other than equirectangular or fields that do not fit.
std::string photo_sphere_spec(const PhotoSphere& ps, Size size);

// The fields describing an equirect projection (full or partial) on its own frame.
PhotoSphere photo_sphere_of(const Equirect& e);

// The XMP packet (an XML document) holding ps's fields, and its insertion into a JPEG file's bytes
// (an APP1 segment after its JFIF and EXIF segments) or a PNG file's (an iTXt chunk after IHDR),
// replacing none: a new file has no XMP. Throws panoproj::Error for other bytes.
std::string photo_sphere_xmp(const PhotoSphere& ps);
struct XmpInsertion {
  size_t offset;      // where in the file
  std::string bytes;  // the segment or chunk to insert there
};
XmpInsertion xmp_insertion(std::string_view file_bytes, const std::string& xmp);
std::string with_xmp(const std::string& file_bytes, const std::string& xmp);  // the file with it inserted

}  // namespace panoproj
