#pragma once
// A source frame's photometric correction from its spec's photometric keys
// (spec/photometric_keys.hpp), for every job on the Converter (convert, views, tiles, Python's
// Plan): each pixel's code values corrected by its lens's model as stitch corrects a project's
// samples (photometric.hpp: R_out(R^-1(c) 2^(ev - E) / V / wb)), into lens 0's response at the
// output's exposure E, before the frame is sampled. In the source's sample type (integers
// rounded): the kernels, seams and two-lens blends then see matched values. A two-lens frame
// (dual-fisheye, gopro-max) takes each pixel's lens's model; a stereo frame's eyes are each a
// frame of the model.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "panoproj/convert.hpp"
#include "panoproj/spec.hpp"
#include "photometry/photometric.hpp"

namespace panoproj {

// Lens `lens`'s model from a spec's keys (lens 1: the keys ending in 2), for samples that are
// float or not (the default response). Throws Error naming `what`.
Photometry lens_photometry(const ProjectionSpec& spec, int lens, bool float_samples,
                           const std::string& what);

class SourceCorrection {
 public:
  // Null where neither spec gives a photometric key. source: one eye's frame at the spec's size.
  // Throws Error naming the spec: target keys other than ev=, vignetting on a gopro-max frame (its
  // cells are no lens's image), a model photometric.hpp refuses.
  static std::shared_ptr<const SourceCorrection> make(const ProjectionSpec& from,
                                                      const ProjectionSpec& to,
                                                      const Projection& source,
                                                      StereoLayout stereo);
  SourceCorrection(const SourceCorrection&) = delete;  // (max_ points into source_)
  SourceCorrection& operator=(const SourceCorrection&) = delete;
  // Whether it keeps every value of a source of `type`.
  bool identity(PixelType type) const;
  // src (the frame, or a window of it, at any decode scale) corrected into out: src's layout,
  // window and alpha (not corrected).
  void apply(const Image& src, Image& out, int threads) const;

 private:
  struct Lens {
    std::optional<PhotometricStep> integer, floating;  // for each kind of sample
    PixelRect rect;                                    // its image in the eye's frame
    const PhotometricStep& step(PixelType t) const {
      return t == PixelType::F16 || t == PixelType::F32 ? *floating : *integer;
    }
  };
  SourceCorrection(Projection source, StereoLayout stereo)
      : source_(std::move(source)), stereo_(stereo) {}
  int lens_at(double x, double y) const;  // in the eye's frame
  Projection source_;
  const GoProMax* max_ = nullptr;  // source_'s, where it is one: its lens_at says a cell's lens
  StereoLayout stereo_ = StereoLayout::Mono;
  std::vector<Lens> lenses_;
};

}  // namespace panoproj
