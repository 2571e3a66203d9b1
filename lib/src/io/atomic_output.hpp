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

// A folder of many files that lands whole (tile pyramids): its files are written into a
// temporary folder beside `path` (made exclusively, random name), each write checked but not
// synced one by one; commit() syncs the file system once (syncfs) and renames the temporary
// folder onto `path` (an existing folder, only with overwrite, is moved aside first, restored if
// the rename fails, removed after). Not committed, the temporary folder is removed with all it
// holds: by the destructor, and on SIGINT / SIGTERM / SIGHUP once install_signal_cleanup() ran.
// A file of an OutputFolder: its path within the folder and its text.
struct TextFile {
  std::string path, text;
};

class OutputFolder {
 public:
  // inputs: the files the job reads; one inside `path` (which overwrite would replace) is refused.
  OutputFolder(std::string path, bool overwrite, const std::vector<std::string>& inputs);
  // Adopts a temporary folder another OutputFolder made and kept (keep(): a scheduler's client
  // made it, workers filled it).
  OutputFolder(std::string path, bool overwrite, std::string staged);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;
  const std::string& staged() const { return staged_; }
  // Leaves the temporary folder in place (to be adopted or removed by remove_staged).
  void keep();
  void commit();
  // Writes a new file at `relative` (subfolders made) in a temporary folder; thread-safe; throws
  // Error naming the file and the system's reason.
  static void write_file(const std::string& staged, const std::string& relative, std::string_view bytes);
  // Removes a kept temporary folder and all it holds.
  static void remove_staged(const std::string& staged);

 private:
  std::string path_, staged_;
  bool overwrite_;
  int slot_ = -1;
  bool done_ = false;
};

}  // namespace panoproj
