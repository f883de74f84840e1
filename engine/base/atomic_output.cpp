#include "engine/base/atomic_output.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "engine/base/error.h"
#include "engine/base/text_file.h"

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
    // What the link ends at names the refusal when it is no regular file
    // (/dev/stdout ends at a pipe or a terminal).
    struct stat target {};
    if (::stat(path.c_str(), &target) == 0 && !S_ISREG(target.st_mode)) {
      st = target;
    } else {
      throw Error(ExitCode::kCantCreate,
                  path + ": cannot create output: is a symbolic link; bristle never writes "
                         "through a link nor replaces it (name the file itself)");
    }
  }
  if (!S_ISREG(st.st_mode))
    throw Error(ExitCode::kCantCreate, path + ": cannot create output: " + fileKindOf(st.st_mode) +
                                           "; an output must be a regular file");
  return path;
}

namespace {

// The open group, for the whole process: an output finished on a worker
// thread joins it too. Outputs are committed one at a time (no lock).
CommitGroup* g_open_group = nullptr;

std::string folderOf(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

// Creates `name` beneath the folder dirfd exclusively, never through a link.
// A leftover of our own PID (a process before us that was killed) is removed
// first: unlink never follows a link, and O_EXCL still guards the create.
int createExclusive(int dirfd, const std::string& name, const std::string& shown) {
  const int flags = O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC;
  int fd = ::openat(dirfd, name.c_str(), flags, 0666);
  if (fd < 0 && errno == EEXIST && ::unlinkat(dirfd, name.c_str(), 0) == 0)
    fd = ::openat(dirfd, name.c_str(), flags, 0666);
  if (fd < 0)
    throw Error(ExitCode::kCantCreate, shown + ": cannot create output: " + std::strerror(errno));
  return fd;
}

// Makes a rename in the folder durable. A file system that cannot sync a
// folder (EINVAL) has nothing to make durable; other failures are ignored
// too: the outputs are in place and complete, only their durability is open.
void syncFolder(int dirfd) { ::fsync(dirfd); }

void syncFolder(const std::string& folder) {
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  syncFolder(fd);
  ::close(fd);
}

// A stream buffer over the temporary file's descriptor that keeps the errno
// of the first failed write, so that the error names why (a full disk, a
// file size limit) even when it is noticed only at commit().
class FdBuf : public std::streambuf {
 public:
  explicit FdBuf(int fd) : fd_(fd) { setp(buf_, buf_ + sizeof buf_); }
  int error() const { return error_; }

 protected:
  int_type overflow(int_type c) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  bool drain() {
    const char* at = pbase();
    while (error_ == 0 && at < pptr()) {
      const ssize_t n = ::write(fd_, at, static_cast<size_t>(pptr() - at));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) error_ = n < 0 ? errno : EIO;
      else at += n;
    }
    setp(buf_, buf_ + sizeof buf_);
    return error_ == 0;
  }
  int fd_;
  int error_ = 0;
  char buf_[1 << 16];
};

Error writeFailed(const std::string& path, int error) {
  return Error(ExitCode::kIoError,
               path + ": write failed: " + (error != 0 ? std::strerror(error) : "unknown error"));
}

// Renames one finished temporary file over its target, then syncs the folder.
void renameIntoPlace(PendingOutput* p) {
  if (std::rename(p->tmp.c_str(), p->path.c_str()) != 0)
    throw Error(ExitCode::kCantCreate, p->path + ": cannot create output: " + std::strerror(errno));
  p->tmp.clear();
  p->registration.reset();
  syncFolder(folderOf(p->path));
}

}  // namespace

PendingOutput::~PendingOutput() {
  if (!tmp.empty()) ::unlink(tmp.c_str());
}

AtomicOutput::AtomicOutput(const std::string& path)
    : path_(path), pending_(std::make_unique<PendingOutput>()) {
  pending_->path = path;
  outputTarget(path);
  const std::string tmp = tempNameFor(path);
  pending_->registration.emplace(tmp);  // before the file exists: a signal removes it
  fd_ = createExclusive(AT_FDCWD, tmp, path);
  pending_->tmp = tmp;
  buf_ = std::make_unique<FdBuf>(fd_);
  out_.rdbuf(buf_.get());
}

AtomicOutput::~AtomicOutput() {
  if (fd_ >= 0) ::close(fd_);
  // pending_ removes the temporary file unless it was renamed or handed on.
}

void AtomicOutput::commit() {
  out_.flush();
  int error = static_cast<FdBuf*>(buf_.get())->error();
  if (error == 0 && !out_) error = EIO;  // a failure the buffer did not see
  if (error == 0 && ::fsync(fd_) != 0) error = errno;
  if (::close(fd_) != 0 && error == 0) error = errno;
  fd_ = -1;
  out_.setstate(std::ios::badbit);  // nothing more goes to a closed file
  if (error != 0) {
    pending_.reset();  // removes the temporary file
    throw writeFailed(path_, error);
  }
  if (CommitGroup* group = g_open_group) {
    group->pending_.push_back(std::move(pending_));
    return;
  }
  renameIntoPlace(pending_.get());
}

CommitGroup::CommitGroup() : outer_(g_open_group) { g_open_group = this; }

CommitGroup::~CommitGroup() {
  if (g_open_group == this) g_open_group = outer_;
  // pending_ removes every temporary file not renamed.
}

CommitGroup* CommitGroup::open() { return g_open_group; }

void CommitGroup::commit() {
  if (g_open_group == this) g_open_group = outer_;
  if (outer_ != nullptr) {
    for (auto& p : pending_) outer_->pending_.push_back(std::move(p));
    for (auto& f : last_) outer_->last_.push_back(std::move(f));
    pending_.clear();
    last_.clear();
    return;
  }
  // Every target is checked before the first rename, so that one turned into
  // a folder or a link meanwhile fails the run with nothing renamed.
  for (const auto& p : pending_) outputTarget(p->path);
  for (auto& p : pending_) renameIntoPlace(p.get());
  pending_.clear();
  std::vector<std::function<void()>> last = std::move(last_);
  last_.clear();
  for (auto& f : last) f();
}

void CommitGroup::atCommit(std::function<void()> last) { last_.push_back(std::move(last)); }

void writeFileAtomically(const std::string& path, std::string_view bytes) {
  AtomicOutput out(path);
  out.write(bytes);
  out.commit();
}

void checkCanCreate(const std::string& path) {
  outputTarget(path);
  const std::string probe = tempNameFor(path) + "-probe";
  const TempFileRegistration registration(probe);
  const int fd = createExclusive(AT_FDCWD, probe, path);
  ::close(fd);
  ::unlink(probe.c_str());
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
  const int fd = createExclusive(dir.fd(), tmp, shown);
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += static_cast<size_t>(n);
  }
  int error = errno;
  const bool synced = done == bytes.size() && ::fsync(fd) == 0;
  if (done == bytes.size() && !synced) error = errno;
  const bool closed = ::close(fd) == 0;
  if (synced && !closed) error = errno;
  if (!synced || !closed) {
    ::unlinkat(dir.fd(), tmp.c_str(), 0);
    throw writeFailed(shown, error);
  }
  if (::renameat(dir.fd(), tmp.c_str(), dir.fd(), name.c_str()) != 0) {
    const int rename_errno = errno;
    ::unlinkat(dir.fd(), tmp.c_str(), 0);
    throw Error(ExitCode::kCantCreate, shown + ": cannot create output: " + std::strerror(rename_errno));
  }
  syncFolder(dir.fd());
}

void moveFileBeneath(const std::string& from, const std::string& root,
                     const std::string& relative) {
  std::string name;
  const Folder dir(openParentBeneath(root, relative, true, &name));
  if (::renameat(AT_FDCWD, from.c_str(), dir.fd(), name.c_str()) == 0) {
    syncFolder(dir.fd());
    return;
  }
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
