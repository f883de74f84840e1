#include "engine/atomic_output.h"

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
}

void checkCanCreate(const std::string& path) {
  const std::string probe = tempNameFor(outputTarget(path)) + "-probe";
  std::FILE* f = std::fopen(probe.c_str(), "wb");
  if (!f) throw Error(ExitCode::kCantCreate, path + ": cannot create output: " + std::strerror(errno));
  std::fclose(f);
  std::remove(probe.c_str());
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
