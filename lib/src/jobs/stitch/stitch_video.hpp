#pragma once
// Stitch's inputs as videos (a rig's, or a template project's --images): every input a video,
// read in step, frame n of each making the panorama's frame n, written as a video (the output
// names a video container: pano.mp4) with the first input's audio and other streams copied and
// spherical metadata where the container and projection have it (as convert writes it). The
// plan (margins, extents, seams) is the same for every frame: only the samples change.
#include <string>

#include "jobs/stitch/stitch.hpp"
#include "panoproj/io.hpp"
#include "panoproj/jobs.hpp"

namespace panoproj {

// A video input's frames as an image's info (RGB, 8 or 16 bits); opens it through the video
// plugin (throws Error naming it).
ImageInfo video_frames_info(const std::string& path);

// Checks the outputs a plan of video inputs can make: a video file (its container and encoder),
// no image options; throws Error naming the value.
void check_video_output(const Arguments& args, const StitchPlan& plan);

// The panorama of each frame, written as plan.panorama (landed whole, or not at all). Inputs
// whose frame rates differ are refused before any frame; one that ends before the others ends
// the job with an error, nothing written.
Report run_stitch_video(StitchPlan plan, const JobEvents& events);

}  // namespace panoproj
