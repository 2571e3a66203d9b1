#include "io/atomic_output.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "panoproj/error.hpp"
#include "panoproj/io.hpp"

namespace panoproj {
namespace fs = std::filesystem;
namespace {

// Temporaries (and, during a commit, moved-aside old files) that a signal must clean up. Plain
// arrays and atomics: the handler may only call async-signal-safe functions (unlink, rename).
struct Slot {
  std::atomic<int> state{0};  // 0 free, 1 being filled, 2 live
  char temp[4096];
  char restore_to[4096];  // "" : unlink temp; else rename temp back to this path
  bool tree;              // temp is a folder: removed with all it holds
};
std::array<Slot, 64> slots;

int claim(const std::string& temp, const std::string& restore_to = {}, bool tree = false) {
  if (temp.size() >= sizeof slots[0].temp || restore_to.size() >= sizeof slots[0].restore_to) return -1;
  for (size_t i = 0; i < slots.size(); ++i) {
    int expected = 0;
    if (!slots[i].state.compare_exchange_strong(expected, 1)) continue;
    std::memcpy(slots[i].temp, temp.c_str(), temp.size() + 1);
    std::memcpy(slots[i].restore_to, restore_to.c_str(), restore_to.size() + 1);
    slots[i].tree = tree;
    slots[i].state = 2;
    return static_cast<int>(i);
  }
  return -1;  // more than 64 at once: still removed by the destructor, not by a signal
}

void release(int slot) {
  if (slot >= 0) slots[static_cast<size_t>(slot)].state = 0;
}

// Removes name (in the folder parent) and, if a folder, all it holds, with system calls only
// (async-signal-safe). Entries are read again from the start until a pass removes none.
void remove_tree_at(int parent, const char* name, int depth) {
  const int fd = depth > 16 ? -1 : ::openat(parent, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) {
    (void)::unlinkat(parent, name, 0);
    return;
  }
  alignas(8) char buf[4096];
  for (bool removed = true; removed;) {
    removed = false;
    (void)::lseek(fd, 0, SEEK_SET);
    for (ssize_t n; (n = ::getdents64(fd, buf, sizeof buf)) > 0;)
      for (ssize_t at = 0; at < n;) {
        const auto* d = reinterpret_cast<const struct dirent64*>(buf + at);
        at += d->d_reclen;
        if (d->d_name[0] == '.' && (!d->d_name[1] || (d->d_name[1] == '.' && !d->d_name[2]))) continue;
        if (d->d_type == DT_DIR) remove_tree_at(fd, d->d_name, depth + 1);
        else (void)::unlinkat(fd, d->d_name, 0);
        removed = true;
      }
  }
  ::close(fd);
  (void)::unlinkat(parent, name, AT_REMOVEDIR);
}

extern "C" void cleanup_and_reraise(int sig) {
  for (Slot& s : slots) {
    if (s.state.load() != 2) continue;
    if (s.restore_to[0]) (void)::rename(s.temp, s.restore_to);
    else if (s.tree) remove_tree_at(AT_FDCWD, s.temp, 0);
    else (void)::unlink(s.temp);
  }
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

std::string reason(int err) { return std::strerror(err); }

[[noreturn]] void fail(const std::string& path, const std::string& why, int err) {
  throw Error("cannot write " + path + ": " + why + " (" + reason(err) + ")", ErrorKind::File);
}

// ".panoproj-<16 hex>.tmp" in path's folder.
std::string random_sibling(const std::string& path) {
  uint64_t r = 0;
  if (::getrandom(&r, sizeof r, 0) != static_cast<ssize_t>(sizeof r)) {
    r = static_cast<uint64_t>(::getpid()) * 0x9E3779B97F4A7C15ull ^ reinterpret_cast<uintptr_t>(&r);
  }
  char name[40];
  std::snprintf(name, sizeof name, ".panoproj-%016llx.tmp", static_cast<unsigned long long>(r));
  return (fs::path(path).parent_path() / name).string();
}

// Writes the pieces to fd one after the other, every write checked (EINTR retried); on failure
// closes fd and throws naming path and the byte it stopped at.
void write_pieces(int fd, const std::string& path, std::span<const std::string_view> pieces) {
  size_t total = 0, written = 0;
  for (const std::string_view piece : pieces) total += piece.size();
  for (const std::string_view piece : pieces) {
    const char* p = piece.data();
    size_t left = piece.size();
    while (left > 0) {
      const ssize_t n = ::write(fd, p, left);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        const int err = n < 0 ? errno : ENOSPC;
        ::close(fd);
        char at[64];
        std::snprintf(at, sizeof at, "writing byte %zu of %zu", written, total);
        fail(path, at, err);
      }
      p += n, written += static_cast<size_t>(n);
      left -= static_cast<size_t>(n);
    }
  }
}

bool lexists(const std::string& path, struct stat* st) { return ::lstat(path.c_str(), st) == 0; }

void sync_folder(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  const fs::path dir = parent.empty() ? fs::path(".") : parent;
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  (void)::fsync(fd);  // best effort: the renames are done, a failure here loses nothing
  ::close(fd);
}

}  // namespace

void install_signal_cleanup() {
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction sa {};
    sa.sa_handler = cleanup_and_reraise;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND;
    ::sigaction(sig, &sa, nullptr);
  }
}

void check_output_path(const std::string& path, bool overwrite) {
  if (path.empty()) throw Error("output: an empty path (give a file name)");
  struct stat st {};
  if (lexists(path, &st)) {
    if (S_ISDIR(st.st_mode)) throw Error("output " + path + " is a directory (give a file name)", ErrorKind::File);
    if (!overwrite)
      throw Error("output " + path + " exists" + (S_ISLNK(st.st_mode) ? " (a link)" : "") + " (pass " +
                      option_text("overwrite") + " to replace it)",
                  ErrorKind::Exists);
    if (!S_ISREG(st.st_mode) && !S_ISLNK(st.st_mode))
      throw Error("output " + path + " is not a regular file (give a file name)", ErrorKind::File);
  }
  const fs::path dir = fs::path(path).parent_path();
  struct stat ds {};
  if (!dir.empty() && (::stat(dir.c_str(), &ds) != 0 || !S_ISDIR(ds.st_mode)))
    throw Error("output folder " + dir.string() + " does not exist (create it first)", ErrorKind::Missing);
}

OutputSet::~OutputSet() {
  for (const Staged& s : staged_) {
    (void)::unlink(s.temp.c_str());
    release(s.slot);
  }
}

void OutputSet::add(const std::string& path, std::span<const std::string_view> pieces) {
  check_output_path(path, overwrite_);
  std::string temp;
  int fd = -1;
  for (int attempt = 0; attempt < 8 && fd < 0; ++attempt) {
    temp = random_sibling(path);
    fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) fail(path, "cannot create a file in its folder", errno);
  }
  if (fd < 0) fail(path, "no free temporary name", EEXIST);
  staged_.push_back({path, temp, claim(temp)});
  write_pieces(fd, path, pieces);
  if (::fsync(fd) != 0) {
    const int err = errno;
    ::close(fd);
    fail(path, "syncing it to disk", err);
  }
  if (::close(fd) != 0) fail(path, "closing it", errno);
}

void OutputSet::commit() {
  // Old files are moved aside (restored on failure or by a signal) so that a set lands whole.
  struct Moved {
    std::string path, aside;
    int slot;
  };
  std::vector<Moved> moved;
  std::vector<size_t> placed;
  auto roll_back = [&] {
    for (size_t i : placed) (void)::unlink(staged_[i].path.c_str());
    for (const Moved& m : moved) {
      (void)::rename(m.aside.c_str(), m.path.c_str());
      release(m.slot);
    }
  };
  const bool several = staged_.size() > 1;
  for (size_t i = 0; i < staged_.size(); ++i) {
    const Staged& s = staged_[i];
    struct stat st {};
    if (lexists(s.path, &st)) {
      if (!overwrite_ || S_ISDIR(st.st_mode)) {
        roll_back();
        check_output_path(s.path, overwrite_);  // says why
      }
      if (several) {
        const std::string aside = random_sibling(s.path);
        if (::renameat2(AT_FDCWD, s.path.c_str(), AT_FDCWD, aside.c_str(), RENAME_NOREPLACE) != 0) {
          const int err = errno;
          roll_back();
          fail(s.path, "moving the old file aside", err);
        }
        moved.push_back({s.path, aside, claim(aside, s.path)});
      }
    }
    // Without overwrite a file created meanwhile is not replaced.
    const unsigned flags = overwrite_ ? 0 : RENAME_NOREPLACE;
    if (::renameat2(AT_FDCWD, s.temp.c_str(), AT_FDCWD, s.path.c_str(), flags) != 0) {
      const int err = errno;
      roll_back();
      if (err == EEXIST) check_output_path(s.path, overwrite_);
      fail(s.path, "renaming it into place", err);
    }
    placed.push_back(i);
  }
  for (const Moved& m : moved) {
    (void)::unlink(m.aside.c_str());
    release(m.slot);
  }
  for (Staged& s : staged_) release(s.slot);
  if (!staged_.empty()) sync_folder(staged_.front().path);
  staged_.clear();
}

namespace {

// Throws unless path may become the output folder.
void check_output_folder(const std::string& path, bool overwrite) {
  struct stat st {};
  if (lexists(path, &st)) {
    if (!S_ISDIR(st.st_mode))
      throw Error("output " + path + " exists and is not a folder (give a new folder's name)", ErrorKind::File);
    if (!overwrite)
      throw Error("output " + path + " exists (pass " + option_text("overwrite") + " to replace the folder)",
                  ErrorKind::Exists);
  }
  const fs::path dir = fs::path(path).parent_path();
  struct stat ds {};
  if (!dir.empty() && (::stat(dir.c_str(), &ds) != 0 || !S_ISDIR(ds.st_mode)))
    throw Error("output folder " + dir.string() + " does not exist (create it first)", ErrorKind::Missing);
}

// Throws unless every input lies outside `path` (an existing folder that overwrite would replace).
void require_outside(const std::string& path, const std::vector<std::string>& inputs) {
  std::error_code ec;
  const fs::path folder = fs::canonical(path, ec);
  if (ec) return;  // not there: nothing to replace
  for (const std::string& input : inputs) {
    const fs::path in = fs::weakly_canonical(input, ec);
    if (ec) continue;
    const auto [f, i] = std::mismatch(folder.begin(), folder.end(), in.begin(), in.end());
    if (f == folder.end())
      throw Error("input " + input + " is inside the output folder " + path +
                  ", which the job replaces (write the output elsewhere)");
  }
}

}  // namespace

OutputFolder::OutputFolder(std::string path, bool overwrite, const std::vector<std::string>& inputs)
    : path_(std::move(path)), overwrite_(overwrite) {
  while (path_.size() > 1 && path_.back() == '/') path_.pop_back();
  if (path_.empty()) throw Error("output: an empty folder name");
  check_output_folder(path_, overwrite_);
  require_outside(path_, inputs);
  for (int attempt = 0; attempt < 8 && staged_.empty(); ++attempt) {
    const std::string temp = random_sibling(path_);
    if (::mkdir(temp.c_str(), 0777) == 0) staged_ = temp;
    else if (errno != EEXIST) fail(path_, "cannot create a folder beside it", errno);
  }
  if (staged_.empty()) fail(path_, "no free temporary name", EEXIST);
  slot_ = claim(staged_, {}, true);
}

OutputFolder::OutputFolder(std::string path, bool overwrite, std::string staged)
    : path_(std::move(path)), staged_(std::move(staged)), overwrite_(overwrite) {
  while (path_.size() > 1 && path_.back() == '/') path_.pop_back();
  struct stat st {};
  if (!lexists(staged_, &st) || !S_ISDIR(st.st_mode))
    throw Error("temporary folder " + staged_ + " is gone (was the job interrupted?)", ErrorKind::Missing);
  slot_ = claim(staged_, {}, true);
}

OutputFolder::~OutputFolder() {
  if (!done_) {
    std::error_code ec;
    fs::remove_all(staged_, ec);
  }
  release(slot_);
}

void OutputFolder::keep() {
  done_ = true;
  release(slot_);
  slot_ = -1;
}

void OutputFolder::write_file(const std::string& staged, const std::string& relative, std::string_view bytes) {
  const fs::path path = fs::path(staged) / relative;
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  if (ec) fail(path.string(), "cannot create its folder", ec.value());
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0) fail(path.string(), "cannot create it", errno);
  write_pieces(fd, path.string(), std::span(&bytes, 1));
  if (::close(fd) != 0) fail(path.string(), "closing it", errno);
}

void OutputFolder::remove_staged(const std::string& staged) {
  std::error_code ec;
  fs::remove_all(staged, ec);
}

void OutputFolder::commit() {
  // One sync for every file written (each write was checked; syncfs reports a failed writeback).
  const int fd = ::open(staged_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) fail(path_, "opening its temporary folder", errno);
  if (::syncfs(fd) != 0) {
    const int err = errno;
    ::close(fd);
    fail(path_, "syncing its files to disk", err);
  }
  ::close(fd);
  std::string aside;
  int aside_slot = -1;
  struct stat st {};
  if (lexists(path_, &st)) {
    check_output_folder(path_, overwrite_);
    aside = random_sibling(path_);
    if (::renameat2(AT_FDCWD, path_.c_str(), AT_FDCWD, aside.c_str(), RENAME_NOREPLACE) != 0)
      fail(path_, "moving the old folder aside", errno);
    aside_slot = claim(aside, path_);
  }
  if (::renameat2(AT_FDCWD, staged_.c_str(), AT_FDCWD, path_.c_str(), RENAME_NOREPLACE) != 0) {
    const int err = errno;
    if (!aside.empty()) (void)::rename(aside.c_str(), path_.c_str());
    release(aside_slot);
    if (err == EEXIST || err == ENOTEMPTY) check_output_folder(path_, false);  // made meanwhile: says so
    fail(path_, "renaming its temporary folder into place", err);
  }
  done_ = true;
  release(slot_);
  slot_ = -1;
  sync_folder(path_);
  if (!aside.empty()) {
    release(aside_slot);
    std::error_code ec;
    fs::remove_all(aside, ec);
  }
}

}  // namespace panoproj
