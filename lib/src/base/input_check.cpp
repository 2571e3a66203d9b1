#include "base/input_check.hpp"

#include <algorithm>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "panoproj/error.hpp"

namespace panoproj {
namespace {

const char* kind_of(mode_t m) {
  if (S_ISDIR(m)) return "a directory";
  if (S_ISFIFO(m)) return "a FIFO";
  if (S_ISCHR(m) || S_ISBLK(m)) return "a device";
  if (S_ISSOCK(m)) return "a socket";
  return "not a regular file";
}

}  // namespace

int open_regular(const std::string& path, uint64_t& bytes, const char* what, const char* expected) {
  const std::string name = std::string(what) + " " + path;
  const std::string shown = std::string(what) == "input" ? path : name;  // "cannot read a.jpg: ..."
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int err = errno;
    if (err == ENOENT || err == ENOTDIR)
      throw Error(name + " does not exist (check the path)", ErrorKind::Missing);
    throw Error("cannot read " + shown + ": " + std::strerror(err), ErrorKind::File);
  }
  if (!S_ISREG(st.st_mode))
    throw Error(
        "cannot read " + shown + ": " + kind_of(st.st_mode) + " (expected " + expected + ")",
        ErrorKind::File);
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) throw Error("cannot read " + shown + ": " + std::strerror(errno), ErrorKind::File);
  struct stat fst {};
  if (::fstat(fd, &fst) != 0 || !S_ISREG(fst.st_mode)) {  // swapped between the two looks
    ::close(fd);
    throw Error("cannot read " + shown + ": not a regular file (expected " + expected + ")",
                ErrorKind::File);
  }
  bytes = static_cast<uint64_t>(fst.st_size);
  return fd;
}

std::string read_fd(int fd, size_t most) {
  // Grown as it fills (doubling from 64 KiB): a small file costs no `most`-sized buffer.
  std::string b;
  size_t got = 0;
  while (got < most) {
    if (got == b.size()) b.resize(std::min(most, std::max<size_t>(2 * b.size(), size_t{1} << 16)));
    const ssize_t n = ::read(fd, b.data() + got, b.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    got += static_cast<size_t>(n);
  }
  b.resize(got);
  return b;
}

std::string read_head(const std::string& path, size_t most, const char* what,
                      const char* expected) {
  uint64_t bytes = 0;
  const int fd = open_regular(path, bytes, what, expected);
  std::string b = read_fd(fd, most);
  ::close(fd);
  return b;
}

}  // namespace panoproj
