#include "io/atomic_output.hpp"

#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

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
};
std::array<Slot, 64> slots;

int claim(const std::string& temp, const std::string& restore_to = {}) {
  if (temp.size() >= sizeof slots[0].temp || restore_to.size() >= sizeof slots[0].restore_to) return -1;
  for (size_t i = 0; i < slots.size(); ++i) {
    int expected = 0;
    if (!slots[i].state.compare_exchange_strong(expected, 1)) continue;
    std::memcpy(slots[i].temp, temp.c_str(), temp.size() + 1);
    std::memcpy(slots[i].restore_to, restore_to.c_str(), restore_to.size() + 1);
    slots[i].state = 2;
    return static_cast<int>(i);
  }
  return -1;  // more than 64 at once: still removed by the destructor, not by a signal
}

void release(int slot) {
  if (slot >= 0) slots[static_cast<size_t>(slot)].state = 0;
}

extern "C" void cleanup_and_reraise(int sig) {
  for (Slot& s : slots) {
    if (s.state.load() != 2) continue;
    if (s.restore_to[0]) (void)::rename(s.temp, s.restore_to);
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

}  // namespace panoproj
