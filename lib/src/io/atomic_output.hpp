#pragma once
// Outputs that cannot lose data. Every output's folder is opened once and everything after is done
// relative to that handle (openat, mkdirat, renameat2 with O_NOFOLLOW at every component), so a
// path component swapped meanwhile cannot redirect a write.
//
// Temporaries are named ".panoproj-<space>-<pid>-<start time>-<16 hex>.tmp": the process that
// made them, its start time in clock ticks after boot (/proc/<pid>/stat field 22), and a hash of
// the boot and pid namespace its pid belongs to. One of this boot and namespace whose process is
// gone is stale: the next output into the same folder removes it and says so (notice); one whose
// process is alive, or of another machine or container (a shared folder), is never touched, nor
// one of the versions before this naming.
//
// Removal never enters a mount point (statx's STATX_ATTR_MOUNT_ROOT: bind mounts of the same file
// system included).
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "panoproj/io.hpp"

namespace panoproj {

// Single files and face sets. Each file's bytes go to a temporary created exclusively in its
// folder (O_EXCL | O_NOFOLLOW, a name of bounded length), written with every write checked,
// synced and closed. commit() renames every staged file into place; if one rename fails the ones
// before are rolled back (old files restored). A temporary not committed is removed by the
// destructor, and on SIGINT / SIGTERM / SIGHUP once install_signal_cleanup() ran (io.hpp).
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
  // A file written as it is made (a video): the descriptor of its temporary, for reading, writing
  // and seeking; seal() syncs and closes it (on failure it closes it and throws naming `path`).
  // A descriptor not sealed is the caller's to close.
  int open(const std::string& path);
  void seal(int fd, const std::string& path);
  // Renames every staged file onto its path, all or none, then runs `landed` (a batch's count);
  // a signal that comes meanwhile is acted on when both are done. `landed` must not commit.
  void commit(const std::function<void()>& landed = {});

 private:
  struct Staged {
    std::string path, name, temp;  // the output, its name in its folder, the temporary's name
    int dir;                       // the folder, opened once
    int slot;                      // in the signal-cleanup registry
  };
  bool overwrite_;
  std::vector<Staged> staged_;
};

// A file of an OutputFolder: its path within the folder and its text.
struct TextFile {
  std::string path, text;
};

// Writes files into a temporary folder (opened by its identity, StagedFolder); thread-safe.
class FolderWriter {
 public:
  // Opens `staged` (O_NOFOLLOW) and throws unless it is the folder begun (device and inode).
  // shown: the output folder, named in messages instead of the temporary one.
  FolderWriter(const StagedFolder& staged, std::string shown);
  ~FolderWriter();
  FolderWriter(const FolderWriter&) = delete;
  FolderWriter& operator=(const FolderWriter&) = delete;
  // A new file at `relative` (subfolders made, no component followed if a link); throws Error
  // naming shown/relative and the system's reason.
  void write(const std::string& relative, std::string_view bytes) const;
  int fd() const { return fd_; }

 private:
  int fd_ = -1;
  std::string shown_;
};

// The marker at the root of every folder panoproj writes: {"made_by": "panoproj", "job": ...}.
inline constexpr const char* kFolderMarker = "panoproj-output.json";

// A folder of many files that lands whole (tile pyramids, view sets): files are written into a
// temporary folder beside `path` (made exclusively), each write checked but not synced one by one;
// commit() writes the marker, syncs the file system once (syncfs) and renames the temporary folder
// onto `path`. Everything that can refuse is checked when the folder is made, before any work:
// the name (not ".", "..", a mount point), the parent, an existing folder (only with overwrite,
// and only one panoproj made: the marker, or an earlier version's layout; none with a mount point
// inside), inputs inside it (by device and inode, so bind mounts are seen). An existing folder is
// moved aside at commit, restored if the rename fails, removed after. Not committed, the temporary
// folder is removed with all it holds: by the destructor, and on SIGINT / SIGTERM / SIGHUP once
// install_signal_cleanup() ran.
class OutputFolder {
 public:
  // job: the job's name, written in the marker.
  OutputFolder(std::string path, bool overwrite, const std::vector<std::string>& inputs, std::string job);
  // Adopts a temporary folder another OutputFolder made and kept (keep(): a scheduler's client
  // made it, workers filled it); throws unless it is that folder, beside `path`.
  OutputFolder(std::string path, bool overwrite, const StagedFolder& staged, std::string job);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;
  const StagedFolder& staged() const { return staged_; }
  const FolderWriter& writer() const { return *writer_; }
  // Leaves the temporary folder in place (to be adopted or removed by remove_staged).
  void keep();
  void commit();
  // Removes a kept temporary folder and all it holds (if it is still that folder).
  static void remove_staged(const StagedFolder& staged);

 private:
  void open_parent();
  // Whether the temporary folder is still the one made, at its name beside the output.
  bool staged_here() const;
  void remove_own_staged() const;
  std::string path_, name_, job_;
  StagedFolder staged_;
  std::string staged_name_;
  bool overwrite_;
  int parent_ = -1;
  std::unique_ptr<FolderWriter> writer_;
  int slot_ = -1;
  bool done_ = false;
};

// The missing folders of a pattern's outputs ('cube/{face}.jpg', 'frames/{n}.png'): made before
// the files, removed again (each if empty, deepest first) unless keep() is called once the job
// has landed.
class MadeFolders {
 public:
  MadeFolders() = default;
  ~MadeFolders();
  MadeFolders(const MadeFolders&) = delete;
  MadeFolders& operator=(const MadeFolders&) = delete;
  // Makes the folders that hold `paths` where missing; throws naming the folder and the reason.
  void make(const std::vector<std::string>& paths);
  void keep() { made_.clear(); }

 private:
  std::vector<std::string> made_;  // in the order made
};

// The same file by device and inode, or (where either cannot be looked at) the same normalised
// path; a path that cannot be resolved is never taken for another.
bool same_file(const std::string& a, const std::string& b);
// A path made absolute and resolved as far as it exists (links, "..", "."); where it cannot be
// looked at, made absolute and normalised.
std::filesystem::path resolved_path(const std::string& path);

}  // namespace panoproj
