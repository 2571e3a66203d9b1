#include "jobs/convert/video_planes.hpp"

#include <algorithm>
#include <cmath>

#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"

namespace panoproj {
namespace {

// Where a plane's samples sit, from its chroma siting (FFmpeg's AVChromaLocation): cosited with
// the first luma sample of their s = 2^log2 (offset 0.5 / s - 0.5 chroma pixels: -1/4 for 4:2:0),
// centred among them (0), or, vertically, with the second of two rows (+1/4).
Siting siting_of(const VideoPixels& px) {
  if (px.planes < 3 || px.rgb) return {};
  const ChromaSiting s = px.siting;
  const double cx = 0.5 / (1 << px.log2_chroma_w) - 0.5, cy = 0.5 / (1 << px.log2_chroma_h) - 0.5;
  const bool left =
      s == ChromaSiting::Left || s == ChromaSiting::TopLeft || s == ChromaSiting::BottomLeft;
  double y = 0;
  if (s == ChromaSiting::TopLeft || s == ChromaSiting::Top) y = cy;
  if ((s == ChromaSiting::BottomLeft || s == ChromaSiting::Bottom) && px.log2_chroma_h == 1)
    y = 0.25;
  const double x = left ? cx : 0;
  return {x, y, x, y};
}

// A plane's projection at its size: the frame's scaled; FFmpeg's EAC frame (border=ffmpeg) laid
// out anew at the plane's size, as v360 converts each plane (its 2-px borders in the plane's px).
Projection plane_projection(const Projection& p, Size size) {
  const auto* c = std::get_if<Cubemap>(&p);
  if (!c || !c->format().ffmpeg_border) return rescaled(p, size);
  if (size.width < 15 || size.height < 10)
    throw Error("border=ffmpeg needs planes of at least 15x10 px (cells of 5 px)");
  return Cubemap(size, c->format());
}

// Video black of plane p.
uint16_t black_of(const VideoPixels& px, int p) {
  if (px.alpha && p == px.planes - 1) return 0;
  if (px.chroma(p)) return static_cast<uint16_t>(1 << (px.bits - 1));
  return px.full_range ? 0 : static_cast<uint16_t>(16 << (px.bits - 8));
}

// Whether the geometry's eyes hold whole chroma samples (and, for planes converted as they are,
// a cube's faces: cells of whole chroma samples).
bool holds_chroma(const VideoPixels& px, std::pair<int, int> sub, const ConversionGeometry& g) {
  const Size eye = size_of(g.target);
  const auto [lw, lh] = sub;
  if (eye.width % (1 << lw) != 0 || eye.height % (1 << lh) != 0) return false;
  if (px.packed || (lw == 0 && lh == 0)) return true;
  try {
    (void)plane_projection(g.target, {eye.width >> lw, eye.height >> lh});
  } catch (const Error&) {
    return false;
  }
  return true;
}

}  // namespace

void check_video_options(const ConvertOptions& o, bool planes) {
  if (o.engine == Engine::Reference)
    throw Error("a video needs the simd or scalar engine (" + option_text("engine") + ")");
  if (planes && (o.edges.active() || o.add_alpha))
    throw Error(
        "a video's pixels outside the source's field are video black: " + option_text("edges") +
        ", " + option_text("fill") + " and " + option_text("alpha") + " are for images");
}

std::pair<int, int> output_subsampling(const VideoPixels& px, bool encoded) {
  if (px.packed) return encoded ? std::pair{1, 1} : std::pair{0, 0};
  return px.planes >= 3 ? std::pair{px.log2_chroma_w, px.log2_chroma_h} : std::pair{0, 0};
}

ConversionGeometry fit_chroma(const VideoPixels& px, std::pair<int, int> sub,
                              const ConvertOptions& options,
                              const std::function<ConversionGeometry(const ConvertOptions&)>& make,
                              const std::function<void(const std::string&)>& warn) {
  ConversionGeometry g = make(options);
  if (!px.packed)
    require_no_correction(g, "a video's planes",
                          "a response needs RGB (give packed RGB frames: Plan; the command "
                          "decodes a video as RGB for them)");
  if (holds_chroma(px, sub, g)) return g;
  const Size out = g.target_frame();
  std::optional<ConversionGeometry> fitted;
  ConvertOptions o = options;
  const auto [lw, lh] = sub;
  const auto up = [](int64_t v, int log2) { return (v + (1 << log2) - 1) >> log2 << log2; };
  // Each side rounded up, else (a cube's whole faces) the next widths at the same aspect.
  std::vector<Size> sizes = {{up(out.width, lw), up(out.height, lh)}};
  for (int64_t w = out.width + 1; w <= out.width + 64; ++w)
    sizes.push_back(
        {w, std::llround(static_cast<double>(out.height * w) / static_cast<double>(out.width))});
  for (const Size& size : sizes) {
    if (fitted) break;
    o.size = size;
    try {
      ConversionGeometry f = make(o);
      if (holds_chroma(px, sub, f)) fitted = std::move(f);
    } catch (const Error&) {  // (a size the projection does not take: the next)
    }
  }
  const std::string why = "output size " + size_text(out) +
                          " does not hold whole chroma samples of " +
                          (px.packed ? std::string("yuv420p") : px.pixel_format) + " (" +
                          std::to_string(1 << lw) + "x" + std::to_string(1 << lh) + " pixels each" +
                          (g.stereo.target != StereoLayout::Mono ? ", in each eye" : "") + ")";
  if (options.size || !fitted)
    throw Error(why + (fitted ? ": give " + option_number("size", size_text(fitted->target_frame()))
                              : ": give " + option_text("size")));
  warn(why + ": made " + size_text(fitted->target_frame()));
  return std::move(*fitted);
}

VideoPlanes::VideoPlanes(const VideoPixels& px, const ConversionGeometry& frame,
                         const ConvertOptions& options, const std::string& input,
                         const std::string& from_text)
    : px_(px), luma_(frame) {
  const int sw = 1 << px_.log2_chroma_w, sh = 1 << px_.log2_chroma_h;
  const Size eye = size_of(luma_.target);
  luma_converter_.emplace(luma_, options, Keep::MapsAndTaps);
  if (px_.planes >= 3 && !px_.rgb && !px_.packed && (sw > 1 || sh > 1)) {
    chroma_ = luma_;
    const Size se = px_.plane_size(size_of(luma_.source), 1), te = px_.plane_size(eye, 1);
    try {
      chroma_->source = plane_projection(luma_.source, se);
    } catch (const Error& e) {
      throw Error("cannot read " + input + ": its chroma planes of " + size_text(se) + " (" +
                      px_.pixel_format + ") do not hold its " + from_text + " whole: " + e.what(),
                  ErrorKind::File);
    }
    chroma_->target = plane_projection(luma_.target, te);
    chroma_->siting = siting_of(px_);
    chroma_converter_.emplace(*chroma_, options, Keep::MapsAndTaps);
  }
  const Size in = luma_.source_frame();
  for (int p = 0; p < px_.planes; ++p) {
    PlaneMap& m = planes_[static_cast<size_t>(p)];
    m.converter = chroma_ && px_.chroma(p) ? &*chroma_converter_ : &*luma_converter_;
    m.black = black_of(px_, p);
    m.most = static_cast<uint16_t>((1 << px_.bits) - 1);
    if (px_.packed) break;  // (RGB: black is 0, what pixels without a source get)
    // (The first plane of each converter marks its pixels without a source: a full plane in,
    // 0 out only where nothing was sampled.)
    const bool first = p == 0 || (m.converter != planes_[0].converter && p == 1);
    if (first)
      m.none = no_source(*m.converter, px_.plane_size(in, p));
    else
      m.none = planes_[m.converter == planes_[0].converter ? 0 : 1].none;
    m.any_none = std::find(m.none.begin(), m.none.end(), 1) != m.none.end();
  }
}

std::vector<uint8_t> VideoPlanes::no_source(const Converter& c, Size in) const {
  const PixelType type = px_.bits > 8 ? PixelType::U16 : PixelType::U8;
  Image full(in, 1, type);
  if (type == PixelType::U8)
    std::fill(full.data(), full.data() + full.byte_size(), 255);
  else
    std::fill(reinterpret_cast<uint16_t*>(full.data()),
              reinterpret_cast<uint16_t*>(full.data() + full.byte_size()), 65535);
  const Image out = c.run(full);
  std::vector<uint8_t> none(static_cast<size_t>(out.width() * out.height()));
  for (size_t i = 0; i < none.size(); ++i)
    none[i] = type == PixelType::U8 ? out.data()[i] == 0
                                    : reinterpret_cast<const uint16_t*>(out.data())[i] == 0;
  return none;
}

void VideoPlanes::convert_plane(int p, const Image& in, Image& out) const {
  const PlaneMap& m = planes_.at(static_cast<size_t>(p));
  m.converter->run(in, out);
  const size_t n = static_cast<size_t>(out.width() * out.height());
  const uint8_t* none = m.none.data();
  if (out.type() == PixelType::U8) {
    if (!m.any_none) return;
    unsigned char* o = out.data();
    const auto black = static_cast<unsigned char>(m.black);
    for (size_t i = 0; i < n; ++i) o[i] = none[i] ? black : o[i];
    return;
  }
  auto* o = reinterpret_cast<uint16_t*>(out.data());
  if (m.any_none)
    for (size_t i = 0; i < n; ++i) o[i] = none[i] ? m.black : std::min(o[i], m.most);
  else if (m.most < 65535)
    for (size_t i = 0; i < n; ++i) o[i] = std::min(o[i], m.most);
}

void VideoPlanes::convert(const VideoFrame& in, VideoFrame& out) const {
  for (int p = 0; p < px_.planes; ++p)
    convert_plane(p, in.planes[static_cast<size_t>(p)], out.planes[static_cast<size_t>(p)]);
  out.pts = in.pts;
}

}  // namespace panoproj
