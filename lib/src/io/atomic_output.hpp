#pragma once
// Outputs that cannot lose data. Each file's bytes go to a temporary created exclusively in its
// folder (O_EXCL | O_NOFOLLOW, a random name of fixed length, so no planted link is followed and
// no long output name overflows NAME_MAX), written with every write checked, synced and closed.
// commit() then renames every staged file into place; if one rename fails the ones before are
// rolled back (old files restored). A temporary not committed is removed by the destructor, and
// on SIGINT / SIGTERM / SIGHUP once install_signal_cleanup() ran (io.hpp).
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace panoproj {

class OutputSet {
 public:
  explicit OutputSet(bool overwrite) : overwrite_(overwrite) {}
  ~OutputSet();
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  // Writes `bytes` to a temporary beside `path`; throws (naming `path` and the system's reason).
  void add(const std::string& path, std::string_view bytes) { add(path, std::span(&bytes, 1)); }
  // The same for a file in pieces, one after the other (a header and pixels held elsewhere).
  void add(const std::string& path, std::span<const std::string_view> pieces);
  // Renames every staged file onto its path, all or none.
  void commit();

 private:
  struct Staged {
    std::string path, temp;
    int slot;  // in the signal-cleanup registry
  };
  bool overwrite_;
  std::vector<Staged> staged_;
};

}  // namespace panoproj
