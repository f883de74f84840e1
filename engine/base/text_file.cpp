#include "engine/base/text_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <vector>

#include "engine/base/error.h"

namespace bristle {
namespace {

void closeQuietly(int fd) {
  const int saved = errno;
  ::close(fd);
  errno = saved;
}

Error tooLarge(const std::string& path, std::uint64_t bytes, bool at_least) {
  return dataError(path, "size",
                   std::string(at_least ? "more than " : "") + std::to_string(bytes) +
                       " bytes is over the input limit of " + std::to_string(kMaxInputBytes) +
                       " bytes (256 MiB)");
}

}  // namespace

const char* fileKindOf(mode_t mode) {
  if (S_ISDIR(mode)) return "is a directory";
  if (S_ISFIFO(mode)) return "is a FIFO";
  if (S_ISCHR(mode)) return "is a character device";
  if (S_ISBLK(mode)) return "is a block device";
  if (S_ISSOCK(mode)) return "is a socket";
  return "is not a regular file";
}


int openInputFile(const std::string& path, std::string* why) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    *why = std::strerror(errno);
    return -1;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    *why = std::strerror(errno);
    closeQuietly(fd);
    return -1;
  }
  if (!S_ISREG(st.st_mode)) {
    *why = fileKindOf(st.st_mode);
    // A directory keeps its short, familiar reason; anything else says the rule.
    if (!S_ISDIR(st.st_mode)) *why += "; an input must be a regular file";
    closeQuietly(fd);
    return -1;
  }
  return fd;
}

std::string readTextFile(const std::string& path) {
  std::string why;
  const int fd = openInputFile(path, &why);
  if (fd < 0) throw Error(ExitCode::kNoInput, path + ": cannot read: " + why);
  struct stat st {};
  if (::fstat(fd, &st) == 0 && static_cast<std::uint64_t>(st.st_size) > kMaxInputBytes) {
    closeQuietly(fd);
    throw tooLarge(path, static_cast<std::uint64_t>(st.st_size), false);
  }
  // Whatever the size said, read at most one byte more than the limit.
  std::string text;
  text.resize(static_cast<size_t>(st.st_size) + 1);
  size_t got = 0;
  for (;;) {
    if (got == text.size()) {
      if (text.size() > kMaxInputBytes) break;
      text.resize(std::min<std::uint64_t>(kMaxInputBytes + 1, text.size() * 2 + 4096));
    }
    const ssize_t n = ::read(fd, text.data() + got, text.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const std::string reason = std::strerror(errno);
      closeQuietly(fd);
      throw Error(ExitCode::kNoInput, path + ": read error: " + reason);
    }
    if (n == 0) break;
    got += static_cast<size_t>(n);
  }
  ::close(fd);
  if (got > kMaxInputBytes) throw tooLarge(path, kMaxInputBytes, true);
  text.resize(got);
  return text;
}

std::string readStandardInput() {
  if (::isatty(STDIN_FILENO))
    throw Error(ExitCode::kNoInput, std::string(kStdinName) +
                                        ": is a terminal; pipe the input in (... < FILE) or "
                                        "give its path");
  std::string text;
  std::vector<char> buf(1 << 16);
  for (;;) {
    const ssize_t n = ::read(STDIN_FILENO, buf.data(), buf.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw Error(ExitCode::kNoInput, std::string(kStdinName) + ": cannot read: " +
                                                   std::strerror(errno));
    if (n == 0) return text;
    text.append(buf.data(), static_cast<size_t>(n));
    if (text.size() > kMaxInputBytes) throw tooLarge(kStdinName, kMaxInputBytes, true);
  }
}

std::string lineColumnOf(const std::string& text, size_t byte_offset) {
  size_t line = 1, col = 1;
  for (size_t i = 0; i < byte_offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(col);
}

}  // namespace bristle
