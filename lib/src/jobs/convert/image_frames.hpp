#pragma once
// Image files as a video's frames, both ways, for the convert job on a video
// (video_convert.hpp): a list of images read as a clip (one packed RGB(A) plane a frame, at a
// frame rate), and a clip's frames written as images through a pattern with {n} (the frame's
// number from 0), each file landed atomically as the images of a batch are.
#include <memory>
#include <string>
#include <vector>

#include "io/video_plugin.hpp"
#include "panoproj/io.hpp"

namespace panoproj {

// Reads the images' headers: all of one size, 1 to 4 channels of 8 or 16 bits (floats refused:
// a video's samples are integers); throws Error naming the first that is not.
std::unique_ptr<VideoReader> image_list_reader(const std::vector<std::string>& images, double fps);

// Frame n to pattern's {n} (throws Error unless the pattern has {n}; an existing first file is
// refused without overwrite before any work).
std::unique_ptr<VideoWriter> image_sequence_writer(const std::string& pattern,
                                                   const WriteOptions& write);

}  // namespace panoproj
