#include "io/atomic_output.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <set>
#include <utility>

#include "panoproj/error.hpp"
#include "panoproj/interrupt.hpp"

namespace panoproj {
namespace fs = std::filesystem;
namespace {

// Temporaries (and, during a commit, moved-aside old files and folders) that a signal must clean
// up, as names in an open folder. Plain arrays and atomics: the handler may only call
// async-signal-safe functions (unlinkat, renameat, statx, getdents64).
struct Slot {
  std::atomic<int> state{0};  // 0 free, 1 being filled, 2 live
  int dir;                    // the folder holding both names (kept open while the slot is live)
  char temp[256];
  char restore_to[256];  // "" : remove temp; else rename temp back to this name
  bool tree;             // temp is a folder: removed with all it holds if still this one,
  uint64_t device;       // of this device and inode (0: one not looked at yet, removed only
  uint64_t inode;        // if empty)
};
std::array<Slot, 64> slots;

int claim(int dir, const std::string& temp, const std::string& restore_to = {}, bool tree = false,
          const StagedFolder* identity = nullptr) {
  if (temp.size() >= sizeof slots[0].temp || restore_to.size() >= sizeof slots[0].restore_to) return -1;
  for (size_t i = 0; i < slots.size(); ++i) {
    int expected = 0;
    if (!slots[i].state.compare_exchange_strong(expected, 1)) continue;
    slots[i].dir = dir;
    std::memcpy(slots[i].temp, temp.c_str(), temp.size() + 1);
    std::memcpy(slots[i].restore_to, restore_to.c_str(), restore_to.size() + 1);
    slots[i].tree = tree;
    slots[i].device = identity ? identity->device : 0;
    slots[i].inode = identity ? identity->inode : 0;
    slots[i].state = 2;
    return static_cast<int>(i);
  }
  return -1;  // more than 64 at once: still removed by the destructor, not by a signal
}

void release(int slot) {
  if (slot >= 0) slots[static_cast<size_t>(slot)].state = 0;
}

// True when `name` in `dir` is the root of a mount (a bind mount of the same file system
// included), or cannot be looked at: removal does not enter it.
bool mount_root(int dir, const char* name) {
  struct statx sx {};
  if (::statx(dir, name, AT_SYMLINK_NOFOLLOW | AT_NO_AUTOMOUNT, STATX_BASIC_STATS, &sx) != 0) return true;
  if (sx.stx_attributes_mask & STATX_ATTR_MOUNT_ROOT) return (sx.stx_attributes & STATX_ATTR_MOUNT_ROOT) != 0;
  struct stat d {};
  return ::fstat(dir, &d) != 0 || makedev(sx.stx_dev_major, sx.stx_dev_minor) != d.st_dev;
}

bool dot_or_dotdot(const char* n) { return n[0] == '.' && (!n[1] || (n[1] == '.' && !n[2])); }

// Removes `name` (in `dir`) and, if a folder, all it holds, with system calls only
// (async-signal-safe), never entering a mount point (a file that is one the kernel refuses to
// unlink: EBUSY). Entries are read again from the start until a pass removes none. Returns whether
// `name` is gone.
bool remove_tree_at(int dir, const char* name, int depth) {
  if (mount_root(dir, name)) return false;
  const int fd = depth > 64 ? -1 : ::openat(dir, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return ::unlinkat(dir, name, 0) == 0 || errno == ENOENT;
  alignas(8) char buf[4096];
  for (bool removed = true; removed;) {
    removed = false;
    (void)::lseek(fd, 0, SEEK_SET);
    for (ssize_t n; (n = ::getdents64(fd, buf, sizeof buf)) > 0;)
      for (ssize_t at = 0; at < n;) {
        const auto* d = reinterpret_cast<const struct dirent64*>(buf + at);
        at += d->d_reclen;
        if (dot_or_dotdot(d->d_name)) continue;
        if (d->d_type == DT_DIR || d->d_type == DT_UNKNOWN) removed |= remove_tree_at(fd, d->d_name, depth + 1);
        else removed |= ::unlinkat(fd, d->d_name, 0) == 0;
      }
  }
  ::close(fd);
  return ::unlinkat(dir, name, AT_REMOVEDIR) == 0;
}

// Whether `name` in `dir` is the folder of this identity (async-signal-safe).
bool is_folder(int dir, const char* name, uint64_t device, uint64_t inode) {
  struct stat st {};
  return ::fstatat(dir, name, &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISDIR(st.st_mode) &&
         static_cast<uint64_t>(st.st_dev) == device && static_cast<uint64_t>(st.st_ino) == inode;
}

// The prefix of every temporary's name.
constexpr std::string_view kTempPrefix = ".panoproj-";

// Calls each(entry) for the entries of folder `fd` but . and .., until it returns false.
template <class Each>
void each_entry(int fd, Each&& each) {
  const int dup = ::openat(fd, ".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  DIR* d = dup < 0 ? nullptr : ::fdopendir(dup);
  if (!d) {
    if (dup >= 0) ::close(dup);
    return;
  }
  while (const dirent* e = ::readdir(d))
    if (!dot_or_dotdot(e->d_name) && !each(*e)) break;
  ::closedir(d);
}

// A batch's files landed and its size, for the line a signal prints (set_batch_progress).
std::atomic<int64_t> batch_written{0}, batch_total{0};
std::atomic<int> report_fd{STDERR_FILENO};

// Appends n's digits at `at` (async-signal-safe); returns the end.
char* put_number(char* at, int64_t n) {
  char digits[24];
  int k = 0;
  do digits[k++] = static_cast<char>('0' + n % 10), n /= 10;
  while (n > 0 && k < 24);
  while (k > 0) *at++ = digits[--k];
  return at;
}

// "panoproj: interrupted after 7 of 20; 7 written (each whole)" on stderr.
void say_batch_progress() {
  const int64_t total = batch_total.load(), written = batch_written.load();
  if (total <= 1) return;
  char line[160];
  char* at = line;
  auto put = [&](const char* text) {
    while (*text) *at++ = *text++;
  };
  put("\npanoproj: interrupted after ");
  at = put_number(at, written);
  put(" of ");
  at = put_number(at, total);
  put("; ");
  at = put_number(at, written);
  put(" written, each whole, the rest not begun or removed\n");
  (void)!::write(report_fd.load(), line, static_cast<size_t>(at - line));
}

// Commits and the signal handler exclude each other, so that a signal finds each output either
// landed and counted or not begun: commit_gate counts the commits under way (-1: a signal's
// cleanup has begun); a signal that comes during one waits in deferred_signal for the last to end.
std::atomic<int> commit_gate{0}, deferred_signal{0};

// Removes the temporaries, says what a batch had done, and raises `sig` again with its default
// action (in a handler it kills when the handler returns).
void clean_up_and_reraise(int sig) {
  for (Slot& s : slots) {
    if (s.state.load() != 2) continue;
    if (s.restore_to[0]) (void)::renameat(s.dir, s.temp, s.dir, s.restore_to);
    else if (s.tree) {
      if (s.inode == 0)
        (void)::unlinkat(s.dir, s.temp, AT_REMOVEDIR);
      else if (is_folder(s.dir, s.temp, s.device, s.inode))
        (void)remove_tree_at(s.dir, s.temp, 0);
    }
    else (void)::unlinkat(s.dir, s.temp, 0);
  }
  say_batch_progress();
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

extern "C" void on_signal(int sig) {
  int none = 0, idle = 0;
  deferred_signal.compare_exchange_strong(none, sig);
  if (commit_gate.compare_exchange_strong(idle, -1)) clean_up_and_reraise(sig);
}

// A commit's renames and what runs when they are done (its count), whole before a signal acts.
class CommitSection {
 public:
  CommitSection() {
    for (int n = commit_gate.load();; n = commit_gate.load()) {
      if (n < 0 || deferred_signal.load() != 0)
        ::pause();  // the process is about to die of a signal
      else if (commit_gate.compare_exchange_weak(n, n + 1))
        return;
    }
  }
  ~CommitSection() {
    int idle = 0;
    if (commit_gate.fetch_sub(1) == 1 && deferred_signal.load() != 0 &&
        commit_gate.compare_exchange_strong(idle, -1))
      clean_up_and_reraise(deferred_signal.load());
  }
  CommitSection(const CommitSection&) = delete;
  CommitSection& operator=(const CommitSection&) = delete;
};

std::string reason(int err) { return std::strerror(err); }

[[noreturn]] void fail(const std::string& path, const std::string& why, int err) {
  throw Error("cannot write " + path + ": " + why + " (" + reason(err) + ")", ErrorKind::File);
}

// A process's start time in clock ticks after boot (/proc/<pid>/stat field 22); 0 if it is gone
// (or a zombie).
unsigned long long start_time(long pid) {
  char path[64];
  std::snprintf(path, sizeof path, "/proc/%ld/stat", pid);
  FILE* f = std::fopen(path, "re");
  if (!f) return 0;
  char buf[1024];
  const size_t n = std::fread(buf, 1, sizeof buf - 1, f);
  std::fclose(f);
  buf[n] = 0;
  const char* p = std::strrchr(buf, ')');  // the command name may hold spaces and parentheses
  unsigned long long t = 0;
  char state = 0;
  if (!p || std::sscanf(p + 2, "%c %*d %*d %*d %*d %*d %*u %*u %*u %*u %*u %*u %*u %*d %*d %*d %*d %*d %*d %llu", &state, &t) != 2)
    return 0;
  return state == 'Z' || state == 'X' ? 0 : t;  // a zombie is gone, only not yet reaped
}

// Which process ids this process can look up: FNV-1a of the boot's id and the pid namespace. A
// temporary of another machine (a shared folder) or container is never judged by our /proc.
unsigned pid_space() {
  std::string text;
  char buf[128];
  if (FILE* f = std::fopen("/proc/sys/kernel/random/boot_id", "re")) {
    text.append(buf, std::fread(buf, 1, sizeof buf, f));
    std::fclose(f);
  }
  const ssize_t n = ::readlink("/proc/self/ns/pid", buf, sizeof buf);
  if (n > 0) text.append(buf, static_cast<size_t>(n));
  uint32_t h = 2166136261u;
  for (const char c : text) h = (h ^ static_cast<unsigned char>(c)) * 16777619u;
  return h;
}

// ".panoproj-<pid space>-<pid>-<start time>-<16 hex>.tmp".
std::string temp_name() {
  static const long pid = ::getpid();
  static const unsigned long long started = start_time(pid);
  static const unsigned space = pid_space();
  uint64_t r = 0;
  if (::getrandom(&r, sizeof r, 0) != static_cast<ssize_t>(sizeof r))
    r = static_cast<uint64_t>(pid) * 0x9E3779B97F4A7C15ull ^ reinterpret_cast<uintptr_t>(&r);
  char name[112];
  std::snprintf(name, sizeof name, ".panoproj-%08x-%ld-%llu-%016llx.tmp", space, pid, started,
                static_cast<unsigned long long>(r));
  return name;
}

// Removes the stale temporaries in `dir` (shown as `shown`): once per folder and process.
void remove_stale(int dir, const std::string& shown) {
  static std::mutex mutex;
  static std::set<std::pair<dev_t, ino_t>> seen;
  struct stat st {};
  if (::fstat(dir, &st) != 0) return;
  {
    std::lock_guard lock(mutex);
    if (!seen.insert({st.st_dev, st.st_ino}).second) return;
  }
  static const unsigned ours = pid_space();
  std::vector<std::string> stale;
  each_entry(dir, [&](const dirent& e) {
    unsigned space = 0;
    long pid = 0;
    unsigned long long started = 0, r = 0;
    int end = 0;
    if (std::sscanf(e.d_name, ".panoproj-%8x-%ld-%llu-%16llx.tmp%n", &space, &pid, &started, &r, &end) == 4 &&
        e.d_name[end] == 0 && pid > 0 && space == ours && start_time(pid) != started)
      stale.push_back(e.d_name);
    return true;
  });
  for (const std::string& name : stale)
    if (remove_tree_at(dir, name.c_str(), 0))
      notice("removed " + (shown == "." ? name : (fs::path(shown) / name).string()) +
             ", a temporary left by a run that ended without cleaning up");
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

std::string folder_of(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? "." : parent.string();
}

std::string name_of(const std::string& path) { return fs::path(path).filename().string(); }

// The folder that holds `path`, opened (following links, as the caller named it); throws naming it
// when it is missing or not a folder.
int open_folder_of(const std::string& path) {
  const std::string dir = folder_of(path);
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) {
    if (errno == ENOENT || errno == ENOTDIR)
      throw Error("output folder " + dir + " does not exist (create it first)", ErrorKind::Missing);
    fail(path, "cannot open its folder", errno);
  }
  return fd;
}

struct Closer {
  int fd;
  ~Closer() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

void set_batch_progress(int64_t written, int64_t total) {
  batch_written = written;
  batch_total = total;
}

void install_signal_cleanup(int fd) {
  report_fd = fd;
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    ::sigaction(sig, &sa, nullptr);
  }
}

void check_output_path(const std::string& path, bool overwrite, bool folder_made) {
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
  fs::path dir = fs::path(path).parent_path();
  struct stat ds {};
  // (A folder to be made: its nearest existing ancestor must be a folder.)
  while (folder_made && !dir.empty() && ::stat(dir.c_str(), &ds) != 0 &&
         (errno == ENOENT || errno == ENOTDIR))
    dir = dir.parent_path();
  if (!dir.empty() && ::stat(dir.c_str(), &ds) != 0)
    throw Error("output folder " + dir.string() + " does not exist (create it first)", ErrorKind::Missing);
  if (!dir.empty() && !S_ISDIR(ds.st_mode))
    throw Error("output folder " + dir.string() + " is not a folder (give another path)",
                ErrorKind::File);
  const std::string name = name_of(path);
  if (name.empty() || name == "." || name == "..")
    throw Error("output " + path + " names no file (give a file name)", ErrorKind::File);
}

MadeFolders::~MadeFolders() {
  for (auto it = made_.rbegin(); it != made_.rend(); ++it) ::rmdir(it->c_str());  // (only if empty)
}

void MadeFolders::make(const std::vector<std::string>& paths) {
  for (const std::string& path : paths) {
    std::vector<fs::path> missing;
    struct stat st {};
    for (fs::path dir = fs::path(path).parent_path(); !dir.empty() && ::stat(dir.c_str(), &st) != 0;
         dir = dir.parent_path())
      missing.push_back(dir);
    for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
      if (::mkdir(it->c_str(), 0777) != 0 && errno != EEXIST)
        throw Error("cannot make the output folder " + it->string() + ": " + std::strerror(errno),
                    ErrorKind::File);
      made_.push_back(it->string());
    }
  }
}

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ea, eb;
  if (fs::exists(a, ea) && fs::exists(b, eb)) {
    const bool same = fs::equivalent(a, b, ea);
    if (!ea) return same;
  }
  return resolved_path(a) == resolved_path(b);
}

fs::path resolved_path(const std::string& path) {
  // Absolute first: weakly_canonical leaves a relative path none of whose parts exists relative
  // ("r.txt"), but makes "./r.txt" absolute.
  std::error_code ec;
  const fs::path absolute = fs::absolute(path, ec);
  if (ec) return fs::path(path).lexically_normal();
  const fs::path resolved = fs::weakly_canonical(absolute, ec);
  return ec ? absolute.lexically_normal() : resolved;
}

void require_distinct_outputs(const std::vector<std::pair<std::string, std::string>>& outputs) {
  for (size_t i = 0; i < outputs.size(); ++i)
    for (size_t j = i + 1; j < outputs.size(); ++j)
      if (!outputs[i].second.empty() && !outputs[j].second.empty() && same_file(outputs[i].second, outputs[j].second))
        throw Error(outputs[i].first + " and " + outputs[j].first + " both name " + outputs[j].second +
                    " (give each output its own file)");
}

// ---- Single files and face sets ----

OutputSet::~OutputSet() {
  for (const Staged& s : staged_) {
    (void)::unlinkat(s.dir, s.temp.c_str(), 0);
    release(s.slot);
    ::close(s.dir);
  }
}

void OutputSet::add(const std::string& path, std::span<const std::string_view> pieces) {
  const int fd = open(path);
  write_pieces(fd, path, pieces);
  seal(fd, path);
}

void OutputSet::seal(int fd, const std::string& path) {
  if (::fsync(fd) != 0) {
    const int err = errno;
    ::close(fd);
    fail(path, "syncing it to disk", err);
  }
  if (::close(fd) != 0) fail(path, "closing it", errno);
}

int OutputSet::open(const std::string& path) {
  check_output_path(path, overwrite_);
  const int dir = open_folder_of(path);
  remove_stale(dir, folder_of(path));
  std::string temp;
  int fd = -1;
  int slot = -1;
  // (Claimed before it exists: a signal meanwhile finds no file, or ours.)
  for (int attempt = 0; attempt < 8 && fd < 0; ++attempt) {
    temp = temp_name();
    slot = claim(dir, temp);
    fd = ::openat(dir, temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd >= 0) break;
    const int err = errno;
    release(slot);
    if (err != EEXIST) {
      ::close(dir);
      fail(path, "cannot create a file in its folder", err);
    }
  }
  if (fd < 0) {
    ::close(dir);
    fail(path, "no free temporary name", EEXIST);
  }
  try {
    staged_.push_back({path, name_of(path), temp, dir, slot});
  } catch (...) {
    (void)::unlinkat(dir, temp.c_str(), 0);
    release(slot);
    ::close(fd);
    ::close(dir);
    throw;
  }
  return fd;
}

void OutputSet::commit(const std::function<void()>& landed) {
  check_interrupt();  // the last moment a stop leaves nothing written
  const CommitSection section;
  // Old files are moved aside (restored on failure or by a signal) so that a set lands whole.
  struct Moved {
    int dir;
    std::string name, aside;
    int slot;
  };
  std::vector<Moved> moved;
  std::vector<size_t> placed;
  auto roll_back = [&] {
    for (size_t i : placed) (void)::unlinkat(staged_[i].dir, staged_[i].name.c_str(), 0);
    for (const Moved& m : moved) {
      (void)::renameat(m.dir, m.aside.c_str(), m.dir, m.name.c_str());
      release(m.slot);
    }
  };
  const bool several = staged_.size() > 1;
  for (size_t i = 0; i < staged_.size(); ++i) {
    const Staged& s = staged_[i];
    struct stat st {};
    if (::fstatat(s.dir, s.name.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0) {
      if (!overwrite_ || S_ISDIR(st.st_mode)) {
        roll_back();
        check_output_path(s.path, overwrite_);  // says why
      }
      if (several) {
        const std::string aside = temp_name();
        if (::renameat2(s.dir, s.name.c_str(), s.dir, aside.c_str(), RENAME_NOREPLACE) != 0) {
          const int err = errno;
          roll_back();
          fail(s.path, "moving the old file aside", err);
        }
        moved.push_back({s.dir, s.name, aside, claim(s.dir, aside, s.name)});
      }
    }
    // Without overwrite a file created meanwhile is not replaced.
    const unsigned flags = overwrite_ ? 0 : RENAME_NOREPLACE;
    if (::renameat2(s.dir, s.temp.c_str(), s.dir, s.name.c_str(), flags) != 0) {
      const int err = errno;
      roll_back();
      if (err == EEXIST) check_output_path(s.path, overwrite_);
      fail(s.path, "renaming it into place", err);
    }
    placed.push_back(i);
  }
  for (const Moved& m : moved) {
    (void)::unlinkat(m.dir, m.aside.c_str(), 0);
    release(m.slot);
  }
  for (Staged& s : staged_) release(s.slot);
  if (landed) landed();
  for (Staged& s : staged_) {
    (void)::fsync(s.dir);  // best effort: the renames are done, a failure here loses nothing
    ::close(s.dir);
  }
  staged_.clear();
}

// ---- Folders ----

FolderWriter::FolderWriter(const StagedFolder& staged, std::string shown) : shown_(std::move(shown)) {
  fd_ = ::open(staged.path.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  struct stat st {};
  if (fd_ < 0 || ::fstat(fd_, &st) != 0 || st.st_dev != staged.device || st.st_ino != staged.inode) {
    const int err = fd_ < 0 ? errno : 0;
    if (fd_ >= 0) ::close(fd_);
    throw Error("temporary folder " + staged.path + " of " + shown_ +
                    (err == ENOENT ? " is gone (was the job interrupted?)"
                                   : " is not the one the job made (moved or replaced meanwhile): nothing written there"),
                ErrorKind::File);
  }
}

FolderWriter::~FolderWriter() {
  if (fd_ >= 0) ::close(fd_);
}

void FolderWriter::write(const std::string& relative, std::string_view bytes) const {
  const std::string shown = shown_ + "/" + relative;
  std::vector<std::string> parts;
  for (const auto& p : fs::path(relative)) parts.push_back(p.string());
  if (parts.empty() || fs::path(relative).is_absolute())
    throw Error("cannot write " + shown + ": not a path inside the folder", ErrorKind::File);
  int dir = fd_;
  Closer owned{-1};
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    const char* c = parts[i].c_str();
    if (parts[i].empty() || dot_or_dotdot(c)) throw Error("cannot write " + shown + ": not a path inside the folder", ErrorKind::File);
    if (::mkdirat(dir, c, 0777) != 0 && errno != EEXIST) fail(shown, "cannot create its folder", errno);
    const int next = ::openat(dir, c, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (next < 0) fail(shown, "cannot open its folder", errno);
    if (owned.fd >= 0) ::close(owned.fd);
    owned.fd = dir = next;
  }
  if (dot_or_dotdot(parts.back().c_str())) throw Error("cannot write " + shown + ": not a file name", ErrorKind::File);
  const int fd = ::openat(dir, parts.back().c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0) fail(shown, "cannot create it", errno);
  write_pieces(fd, shown, std::span(&bytes, 1));
  if (::close(fd) != 0) fail(shown, "closing it", errno);
}

namespace {

// The names an earlier version's folder held at its root (before the marker), and those it must.
bool earlier_layout(const std::set<std::string>& names) {
  const auto only = [&](std::initializer_list<const char*> allowed, bool digits) {
    for (const std::string& n : names) {
      bool ok = digits && !n.empty() && n.size() < 4 && std::all_of(n.begin(), n.end(), ::isdigit);
      for (const char* a : allowed) ok |= n == a;
      if (!ok) return false;
    }
    return true;
  };
  const auto has = [&](const char* n) { return names.count(n) > 0; };
  const bool tiles = has("config.json") && has("index.html") && only({"config.json", "index.html", "fallback", "tiles"}, true);
  const bool views = has("images") && (has("transforms.json") || has("sparse")) &&
                     only({"images", "masks", "sparse", "transforms.json", "rig_config.json"}, false);
  return tiles || views;
}

// Whether the folder `fd` was made by panoproj: its marker, an earlier version's layout, or empty.
bool made_by_panoproj(int fd) {
  const int marker = ::openat(fd, kFolderMarker, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (marker >= 0) {
    char buf[256] = {};
    const ssize_t n = ::read(marker, buf, sizeof buf - 1);
    ::close(marker);
    if (n > 0 && std::strstr(buf, "\"made_by\": \"panoproj\"")) return true;
  }
  std::set<std::string> names;
  each_entry(fd, [&](const dirent& e) {
    names.insert(e.d_name);
    return names.size() < 4096;
  });
  return names.empty() || earlier_layout(names);
}

// The first mount point inside folder `fd` (a path relative to it), or "".
std::string mount_inside(int fd, const std::string& at, int depth) {
  std::string found;
  each_entry(fd, [&](const dirent& e) {
    const std::string path = at.empty() ? e.d_name : at + "/" + e.d_name;
    if (mount_root(fd, e.d_name)) found = path;
    else if (e.d_type == DT_DIR || e.d_type == DT_UNKNOWN) {
      const int sub = depth > 64 ? -1 : ::openat(fd, e.d_name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
      if (sub >= 0) {
        found = mount_inside(sub, path, depth + 1);
        ::close(sub);
      }
    }
    return found.empty();
  });
  return found;
}

// Throws unless the entry `name` in `parent` (the output `path`) may be replaced by the job's
// folder; with scan_mounts, also if a mount point lies anywhere inside it (before the work: the
// removal after the commit never enters one anyway, and says so).
void check_replaceable(int parent, const std::string& name, const std::string& path, bool overwrite,
                       bool scan_mounts) {
  struct stat st {};
  if (::fstatat(parent, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) return;
  if (!S_ISDIR(st.st_mode))
    throw Error("output " + path + " exists and is not a folder (give a new folder's name)", ErrorKind::File);
  if (!overwrite)
    throw Error("output " + path + " exists (pass " + option_text("overwrite") + " to replace the folder)", ErrorKind::Exists);
  if (mount_root(parent, name.c_str()))
    throw Error("output " + path + " is a mount point, which cannot be replaced (write into a new folder inside it)",
                ErrorKind::File);
  const int fd = ::openat(parent, name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) fail(path, "cannot open the existing folder", errno);
  Closer closer{fd};
  if (!made_by_panoproj(fd))
    throw Error("output " + path + " was not made by panoproj (no " + kFolderMarker +
                    ", not a tile pyramid or view set), so " + option_text("overwrite") +
                    " does not replace it (give a new folder's name, or remove it yourself)",
                ErrorKind::Exists);
  const std::string mount = scan_mounts ? mount_inside(fd, "", 0) : std::string();
  if (!mount.empty())
    throw Error("output " + path + " holds a mount point, " + path + "/" + mount +
                    ", which replacing the folder would reach into (unmount it, or give a new folder's name)",
                ErrorKind::File);
}

// Throws if an input lies inside the existing folder `name` of `parent`, which the job replaces:
// by device and inode of each folder above the input (as named, and with links resolved), so a
// bind mount of the folder is seen.
void require_outside(int parent, const std::string& name, const std::string& path, const std::vector<std::string>& inputs) {
  struct stat out {};
  if (::fstatat(parent, name.c_str(), &out, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISDIR(out.st_mode)) return;
  for (const std::string& input : inputs) {
    std::error_code ec;
    std::vector<fs::path> ways{fs::absolute(input, ec).lexically_normal()};
    const fs::path resolved = fs::weakly_canonical(input, ec);
    if (!ec) ways.push_back(resolved);
    for (const fs::path& way : ways)
      for (fs::path p = way.parent_path();; p = p.parent_path()) {
        struct stat st {};
        if (::stat(p.c_str(), &st) == 0 && st.st_dev == out.st_dev && st.st_ino == out.st_ino)
          throw Error("input " + input + " is inside the output folder " + path +
                      ", which the job replaces (write the output elsewhere)");
        if (p == p.parent_path() || p.empty()) break;
      }
  }
}

std::string marker_text(const std::string& job) {
  return "{\"made_by\": \"panoproj\", \"job\": \"" + job + "\"}\n";
}

}  // namespace

void OutputFolder::open_parent() {
  while (path_.size() > 1 && path_.back() == '/') path_.pop_back();
  if (path_.empty()) throw Error("output: an empty folder name");
  name_ = name_of(path_);
  if (name_.empty() || name_ == "." || name_ == "..")
    throw Error("output " + path_ + " names no new folder (give the folder by its name, not . or ..)", ErrorKind::File);
  parent_ = open_folder_of(path_);
}

OutputFolder::OutputFolder(std::string path, bool overwrite, const std::vector<std::string>& inputs, std::string job)
    : path_(std::move(path)), job_(std::move(job)), overwrite_(overwrite) {
  open_parent();
  try {
    check_replaceable(parent_, name_, path_, overwrite_, true);
    require_outside(parent_, name_, path_, inputs);
    remove_stale(parent_, folder_of(path_));
    // (Claimed before it exists, as an empty folder to remove, then by its identity.)
    for (int attempt = 0; attempt < 8 && staged_name_.empty(); ++attempt) {
      const std::string temp = temp_name();
      slot_ = claim(parent_, temp, {}, true);
      if (::mkdirat(parent_, temp.c_str(), 0777) == 0) staged_name_ = temp;
      else {
        const int err = errno;
        release(slot_);
        slot_ = -1;
        if (err != EEXIST) fail(path_, "cannot create a folder beside it", err);
      }
    }
    if (staged_name_.empty()) fail(path_, "no free temporary name", EEXIST);
    struct stat st {};
    if (::fstatat(parent_, staged_name_.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) fail(path_, "looking at its temporary folder", errno);
    staged_ = {(fs::path(folder_of(path_)) / staged_name_).string(), static_cast<uint64_t>(st.st_dev),
               static_cast<uint64_t>(st.st_ino)};
    const int empty_slot = slot_;
    slot_ = claim(parent_, staged_name_, {}, true, &staged_);
    release(empty_slot);
    writer_ = std::make_unique<FolderWriter>(staged_, path_);
  } catch (...) {
    release(slot_);
    remove_own_staged();
    ::close(parent_);
    throw;
  }
}

OutputFolder::OutputFolder(std::string path, bool overwrite, const StagedFolder& staged, std::string job)
    : path_(std::move(path)), job_(std::move(job)), staged_(staged), overwrite_(overwrite) {
  open_parent();
  staged_name_ = name_of(staged_.path);
  if (!staged_here()) {
    ::close(parent_);
    throw Error("temporary folder " + staged_.path + " is not beside " + path_ +
                    " as the job made it (moved, replaced or removed meanwhile: was the job interrupted?)",
                ErrorKind::Missing);
  }
  slot_ = claim(parent_, staged_name_, {}, true, &staged_);
  try {
    writer_ = std::make_unique<FolderWriter>(staged_, path_);
  } catch (...) {
    release(slot_);
    ::close(parent_);
    throw;
  }
}

OutputFolder::~OutputFolder() {
  writer_.reset();
  release(slot_);
  if (!done_) remove_own_staged();
  ::close(parent_);
}

bool OutputFolder::staged_here() const {
  return name_of(staged_.path) == staged_name_ && staged_name_.starts_with(kTempPrefix) &&
         is_folder(parent_, staged_name_.c_str(), staged_.device, staged_.inode);
}

void OutputFolder::remove_own_staged() const {
  // Only the folder it made: one swapped in at its name (by whoever can write beside it) is left.
  if (!staged_name_.empty() && staged_.inode != 0 && staged_here()) (void)remove_tree_at(parent_, staged_name_.c_str(), 0);
}

void OutputFolder::keep() {
  done_ = true;
  release(slot_);
  slot_ = -1;
}

void OutputFolder::remove_staged(const StagedFolder& staged) {
  const int dir = ::open(folder_of(staged.path).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir < 0) return;
  Closer closer{dir};
  const std::string name = name_of(staged.path);
  if (name.starts_with(kTempPrefix) && is_folder(dir, name.c_str(), staged.device, staged.inode))
    (void)remove_tree_at(dir, name.c_str(), 0);
}

void OutputFolder::commit() {
  check_interrupt();  // the last moment a stop leaves nothing written
  writer_->write(kFolderMarker, marker_text(job_));
  // One sync for every file written (each write was checked; syncfs reports a failed writeback).
  if (::syncfs(writer_->fd()) != 0) fail(path_, "syncing its files to disk", errno);
  if (!staged_here())
    throw Error("cannot write " + path_ + ": its temporary folder " + staged_.path +
                    " was moved or replaced meanwhile (nothing landed)",
                ErrorKind::File);
  std::string aside;
  int aside_slot = -1;
  {
    const CommitSection section;
    struct stat st {};
    if (::fstatat(parent_, name_.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0) {
      check_replaceable(parent_, name_, path_, overwrite_,
                        false);  // again: it may have changed during the work
      aside = temp_name();
      if (::renameat2(parent_, name_.c_str(), parent_, aside.c_str(), RENAME_NOREPLACE) != 0)
        fail(path_, "moving the old folder aside", errno);
      aside_slot = claim(parent_, aside, name_);
    }
    if (::renameat2(parent_, staged_name_.c_str(), parent_, name_.c_str(), RENAME_NOREPLACE) != 0) {
      const int err = errno;
      if (!aside.empty()) (void)::renameat(parent_, aside.c_str(), parent_, name_.c_str());
      release(aside_slot);
      if (err == EEXIST || err == ENOTEMPTY)
        check_replaceable(parent_, name_, path_, false, false);  // made meanwhile: says so
      fail(path_, "renaming its temporary folder into place", err);
    }
    done_ = true;
    release(slot_);
    slot_ = -1;
    release(aside_slot);  // (landed: its removal is not undone by a signal)
  }
  (void)::fsync(parent_);  // best effort: the renames are done, a failure here loses nothing
  if (!aside.empty() && !remove_tree_at(parent_, aside.c_str(), 0))
    throw Error(
        path_ + " landed, but its old folder, moved to " +
            (fs::path(folder_of(path_)) / aside).string() +
            ", could not be removed whole (a mount point appeared inside it?): remove it yourself",
        ErrorKind::File);
}

}  // namespace panoproj
