#include "engine/atomic_output.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "engine/error.h"
#include "engine/text_file.h"

namespace bristle {

namespace {

namespace fs = std::filesystem;

std::string tempNameFor(const std::string& path) {
  return path + ".tmp-" + std::to_string(::getpid());
}

// The same file: device and inode of two existing files (links followed).
bool sameFile(const std::string& a, const std::string& b) {
  struct stat sa {}, sb {};
  if (::stat(a.c_str(), &sa) != 0 || ::stat(b.c_str(), &sb) != 0) return false;
  return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

// Two outputs that do not exist yet are the same when their paths resolve alike.
bool samePath(const std::string& a, const std::string& b) {
  std::error_code ea, eb;
  const fs::path pa = fs::weakly_canonical(fs::absolute(a), ea);
  const fs::path pb = fs::weakly_canonical(fs::absolute(b), eb);
  return !ea && !eb && pa == pb;
}

}  // namespace

std::string outputTarget(const std::string& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return path;  // a new file
  if (S_ISLNK(st.st_mode)) {
    // What the link ends at decides (/dev/stdout ends at a pipe or a terminal).
    // A link to a regular file is kept and its target replaced; a dangling link
    // is replaced itself (weakly_canonical stops at it), never written through.
    const bool exists = ::stat(path.c_str(), &st) == 0;
    if (!exists || S_ISREG(st.st_mode)) {
      std::error_code ec;
      const fs::path resolved = fs::weakly_canonical(fs::absolute(path), ec);
      if (ec)
        throw Error(ExitCode::kCantCreate, path + ": cannot create output: cannot resolve the "
                                                  "symbolic link: " + ec.message());
      return resolved.string();
    }
  }
  if (!S_ISREG(st.st_mode))
    throw Error(ExitCode::kCantCreate, path + ": cannot create output: " + fileKindOf(st.st_mode) +
                                           "; an output must be a regular file");
  return path;
}

AtomicOutput::AtomicOutput(const std::string& path)
    : path_(path), target_(outputTarget(path)), tmp_(tempNameFor(target_)) {
  registration_.emplace(tmp_);
  out_.open(tmp_, std::ios::binary | std::ios::trunc);
  if (!out_)
    throw Error(ExitCode::kCantCreate, path + ": cannot create output: " + std::strerror(errno));
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) {
    out_.close();
    std::remove(tmp_.c_str());
  }
}

void AtomicOutput::commit() {
  out_.flush();
  const bool ok = static_cast<bool>(out_);
  out_.close();
  if (!ok || out_.fail()) {
    std::remove(tmp_.c_str());
    committed_ = true;
    throw Error(ExitCode::kIoError, path_ + ": write failed");
  }
  if (std::rename(tmp_.c_str(), target_.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(tmp_.c_str());
    committed_ = true;
    throw Error(ExitCode::kCantCreate, path_ + ": cannot create output: " + why);
  }
  committed_ = true;
  registration_.reset();
}

void checkCanCreate(const std::string& path) {
  const std::string probe = tempNameFor(outputTarget(path)) + "-probe";
  const TempFileRegistration registration(probe);
  std::FILE* f = std::fopen(probe.c_str(), "wb");
  if (!f) throw Error(ExitCode::kCantCreate, path + ": cannot create output: " + std::strerror(errno));
  std::fclose(f);
  std::remove(probe.c_str());
}

namespace {

// An open folder descriptor, closed on scope exit.
class Folder {
 public:
  explicit Folder(int fd) : fd_(fd) {}
  ~Folder() {
    if (fd_ >= 0) ::close(fd_);
  }
  Folder(const Folder&) = delete;
  Folder& operator=(const Folder&) = delete;
  void reset(int fd) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = fd;
  }
  int fd() const { return fd_; }
  int release() {
    const int fd = fd_;
    fd_ = -1;
    return fd;
  }

 private:
  int fd_;
};

// Walks root/relative's folders without following links; returns the
// descriptor of the last folder (-1 when `create` is false and one is missing)
// and sets *name to the file's name. Throws kCantCreate.
int openParentBeneath(const std::string& root, const std::string& relative, bool create,
                      std::string* name) {
  const std::string shown = (fs::path(root) / relative).string();
  auto refuse = [&](const std::string& why) {
    return Error(ExitCode::kCantCreate, shown + ": cannot create output: " + why);
  };
  const fs::path rel = fs::path(relative).lexically_normal();
  if (rel.is_absolute() || !rel.has_filename() || *rel.begin() == "..")
    throw refuse("not a relative path beneath " + root);
  Folder dir(::open(root.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  if (dir.fd() < 0) throw refuse(root + ": " + std::strerror(errno));
  fs::path walked = root;
  for (const fs::path& part : rel.parent_path()) {
    walked /= part;
    if (part == "." || part.empty()) continue;
    if (part == "..") throw refuse("not a relative path beneath " + root);
    if (create && ::mkdirat(dir.fd(), part.c_str(), 0777) != 0 && errno != EEXIST)
      throw refuse(walked.string() + ": " + std::strerror(errno));
    const int next = ::openat(dir.fd(), part.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (next < 0) {
      const int open_errno = errno;
      struct stat st {};
      if (::fstatat(dir.fd(), part.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISLNK(st.st_mode))
        throw refuse(walked.string() + " is a symbolic link; a batch writes only beneath --out");
      if (open_errno == ENOENT && !create) return -1;
      throw refuse(walked.string() + ": " + std::strerror(open_errno));
    }
    dir.reset(next);
  }
  *name = rel.filename().string();
  struct stat st {};
  if (::fstatat(dir.fd(), name->c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0) {
    if (S_ISLNK(st.st_mode))
      throw refuse("is a symbolic link; a batch writes only beneath --out");
    if (!S_ISREG(st.st_mode))
      throw refuse(std::string(fileKindOf(st.st_mode)) + "; an output must be a regular file");
  }
  return dir.release();
}

}  // namespace

void checkBeneath(const std::string& root, const std::string& relative) {
  std::string name;
  const int fd = openParentBeneath(root, relative, false, &name);
  if (fd >= 0) ::close(fd);
}

void writeFileBeneath(const std::string& root, const std::string& relative,
                      const std::string& bytes) {
  std::string name;
  const Folder dir(openParentBeneath(root, relative, true, &name));
  const std::string shown = (fs::path(root) / relative).string();
  const std::string tmp = name + ".tmp-" + std::to_string(::getpid());
  const TempFileRegistration registration(shown + ".tmp-" + std::to_string(::getpid()));
  const int fd = ::openat(dir.fd(), tmp.c_str(),
                          O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0) throw Error(ExitCode::kCantCreate, shown + ": cannot create output: " + std::strerror(errno));
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += static_cast<size_t>(n);
  }
  const int write_errno = errno;
  const bool closed = ::close(fd) == 0;
  if (done != bytes.size() || !closed) {
    ::unlinkat(dir.fd(), tmp.c_str(), 0);
    throw Error(ExitCode::kIoError, shown + ": write failed: " + std::strerror(write_errno));
  }
  if (::renameat(dir.fd(), tmp.c_str(), dir.fd(), name.c_str()) != 0) {
    const int rename_errno = errno;
    ::unlinkat(dir.fd(), tmp.c_str(), 0);
    throw Error(ExitCode::kCantCreate, shown + ": cannot create output: " + std::strerror(rename_errno));
  }
}

void moveFileBeneath(const std::string& from, const std::string& root,
                     const std::string& relative) {
  std::string name;
  const Folder dir(openParentBeneath(root, relative, true, &name));
  if (::renameat(AT_FDCWD, from.c_str(), dir.fd(), name.c_str()) == 0) return;
  if (errno != EXDEV)
    throw Error(ExitCode::kCantCreate, (fs::path(root) / relative).string() +
                                           ": cannot create output: " + std::strerror(errno));
  writeFileBeneath(root, relative, readTextFile(from));
  ::unlink(from.c_str());
}

void checkOutputs(const std::vector<NamedFile>& outputs, const std::vector<NamedFile>& inputs) {
  for (size_t i = 0; i < outputs.size(); ++i) {
    const NamedFile& out = outputs[i];
    if (out.path.empty()) continue;
    for (const NamedFile& in : inputs)
      if (!in.path.empty() && (sameFile(out.path, in.path) || samePath(out.path, in.path)))
        throw Error(ExitCode::kUsage, out.path + ": " + out.option +
                                          ": is the same file as the input " + in.path + " (" +
                                          in.option + "); an output must not overwrite an input");
    for (size_t j = 0; j < i; ++j)
      if (!outputs[j].path.empty() &&
          (sameFile(out.path, outputs[j].path) || samePath(out.path, outputs[j].path)))
        throw Error(ExitCode::kUsage, out.path + ": " + out.option +
                                          ": is the same file as the output " + outputs[j].path +
                                          " (" + outputs[j].option +
                                          "); give each output its own file");
  }
  for (const NamedFile& out : outputs)
    if (!out.path.empty()) outputTarget(out.path);
}

}  // namespace bristle
