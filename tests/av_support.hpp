#pragma once
// What the video tests read of a file through libavformat directly (an oracle beside the plugin).
extern "C" {
#include <libavformat/avformat.h>
}

#include <string>
#include <vector>

namespace panoproj::test {

// The packets of a file's streams of `type`, in file order (none if it cannot be opened).
inline std::vector<std::string> stream_packets(const std::string& file, AVMediaType type) {
  std::vector<std::string> out;
  AVFormatContext* in = nullptr;
  if (avformat_open_input(&in, file.c_str(), nullptr, nullptr) < 0) return out;
  avformat_find_stream_info(in, nullptr);
  AVPacket* p = av_packet_alloc();
  while (av_read_frame(in, p) >= 0) {
    if (in->streams[p->stream_index]->codecpar->codec_type == type)
      out.emplace_back(reinterpret_cast<const char*>(p->data), static_cast<size_t>(p->size));
    av_packet_unref(p);
  }
  av_packet_free(&p);
  avformat_close_input(&in);
  return out;
}

}  // namespace panoproj::test
