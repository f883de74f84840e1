#include "engine/atomic_output.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "engine/error.h"

namespace bristle {

namespace {
std::string tempNameFor(const std::string& path) {
  return path + ".tmp-" + std::to_string(::getpid());
}
}  // namespace

AtomicOutput::AtomicOutput(const std::string& path) : path_(path), tmp_(tempNameFor(path)) {
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
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(tmp_.c_str());
    committed_ = true;
    throw Error(ExitCode::kCantCreate, path_ + ": cannot create output: " + why);
  }
  committed_ = true;
}

void checkCanCreate(const std::string& path) {
  const std::string probe = tempNameFor(path) + "-probe";
  std::FILE* f = std::fopen(probe.c_str(), "wb");
  if (!f) throw Error(ExitCode::kCantCreate, path + ": cannot create output: " + std::strerror(errno));
  std::fclose(f);
  std::remove(probe.c_str());
}

}  // namespace bristle
