#include "haptics/session_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <sstream>

#include "engine/base/atomic_output.h"
#include "engine/base/error.h"
#include "engine/base/fnv1a64.h"
#include "engine/base/text_file.h"
#include "engine/formats/trajectory_reader.h"
#include "haptics/monotonic_clock.h"

namespace bristle::haptics {

namespace {

// Flushed this often by flushIfDue: well inside the 100 ms promised.
constexpr std::int64_t kFlushEveryNs = 50'000'000;

}  // namespace

std::string brushFileHash(const std::string& brush_path) {
  return hex64(fnv1a64(readTextFile(brush_path)));
}

// A live session is written in place, not through a temporary file: rows
// reach the disk every 50 ms so that a crash keeps the recording
// (docs/haptics.md). Like every output it is a regular file or a new one,
// never a device, a FIFO or a symbolic link (O_NOFOLLOW; engine/base/atomic_output.h).
std::FILE* SessionWriter::open(const std::string& path) {
  outputTarget(path);
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0666);
  std::FILE* f = fd >= 0 ? ::fdopen(fd, "w") : nullptr;
  if (f == nullptr) {
    const int error = errno;
    if (fd >= 0) ::close(fd);
    throw Error(ExitCode::kCantCreate, path + ": cannot create: " + std::strerror(error));
  }
  return f;
}

SessionWriter::SessionWriter(const std::string& session_path, const std::string& forces_path,
                             const SessionHeader& h)
    : session_path_(session_path), forces_path_(forces_path) {
  // Every output can be created before the session file is opened (and an
  // existing one truncated).
  outputTarget(session_path);
  if (!forces_path.empty()) checkCanCreate(forces_path);
  session_ = open(session_path);
  setvbuf(session_, nullptr, _IOLBF, 1 << 16);  // line-buffered
  if (!forces_path.empty()) forces_ = open(forces_path);
  decimation_ = static_cast<std::uint64_t>(
      std::max(1.0, std::round(h.servo_rate_hz / std::max(1.0, h.session_rate_hz))));
  std::fprintf(session_,
               "# bristle-trajectory/1\n"
               "# bristle record: a live session\n"
               "# device: %s\n"
               "# servo_rate_hz: %g\n"
               "# session_rate_hz: %g\n"
               "# units: t_s s, position mm, forces N on the handle in the canvas frame\n"
               "# brush: %s\n"
               "# brush_fnv1a64: %s\n",
               h.device_model.c_str(), h.servo_rate_hz, h.servo_rate_hz / decimation_,
               h.brush_path.c_str(), h.brush_hash.c_str());
  for (const auto& [key, value] : h.options)
    std::fprintf(session_, "# %s: %s\n", key.c_str(), value.c_str());
  std::fprintf(session_, "t_s,x_mm,y_mm,z_mm,qw,qx,qy,qz,buttons,fx_n,fy_n,fz_n\n");
  if (forces_ != nullptr) std::fprintf(forces_, "t_s,fx_n,fy_n,fz_n\n");
  std::fflush(session_);
  last_flush_ns_ = monotonicNs();
}

SessionWriter::~SessionWriter() {
  if (session_ != nullptr) std::fclose(session_);
  if (forces_ != nullptr) std::fclose(forces_);
}

void SessionWriter::add(const ServoSample& s) {
  if (forces_ != nullptr) {
    std::fprintf(forces_, "%.6f,%.6f,%.6f,%.6f\n", s.t_s, s.force_n[0], s.force_n[1],
                 s.force_n[2]);
    ++force_rows_;
  }
  if (s.tick % decimation_ != 0 || s.t_s <= last_t_s_) return;
  last_t_s_ = s.t_s;
  std::fprintf(session_, "%.6f,%.6f,%.6f,%.6f,%.9f,%.9f,%.9f,%.9f,%d,%.6f,%.6f,%.6f\n", s.t_s,
               s.position_mm[0], s.position_mm[1], s.position_mm[2], s.rotation_wxyz[0],
               s.rotation_wxyz[1], s.rotation_wxyz[2], s.rotation_wxyz[3], s.buttons,
               s.force_n[0], s.force_n[1], s.force_n[2]);
  ++rows_;
}

void SessionWriter::flushIfDue() {
  const std::int64_t now = monotonicNs();
  if (now - last_flush_ns_ < kFlushEveryNs) return;
  last_flush_ns_ = now;
  std::fflush(session_);
  if (forces_ != nullptr) std::fflush(forces_);
}

void SessionWriter::close() {
  auto finish = [](std::FILE*& f, const std::string& path) {
    if (f == nullptr) return;
    const bool ok = std::fflush(f) == 0 && ::fsync(fileno(f)) == 0 && !std::ferror(f);
    const int err = errno;
    const bool closed = std::fclose(f) == 0;
    f = nullptr;
    if (!ok || !closed)
      throw Error(ExitCode::kIoError, path + ": write failed: " + std::strerror(err));
  };
  finish(session_, session_path_);
  finish(forces_, forces_path_);
}

Session loadSession(const std::string& path, const std::string& expected_brush_hash) {
  Session s;
  std::string text = readTextFile(path);
  if (!text.empty() && text.back() != '\n') {
    const size_t cut = text.rfind('\n');
    size_t lines = 0;
    for (char c : text) lines += c == '\n';
    s.warnings.push_back(path + ": line " + std::to_string(lines + 1) +
                         ": incomplete (the recording was cut off); replaying up to line " +
                         std::to_string(lines));
    text.erase(cut == std::string::npos ? 0 : cut + 1);
  }
  s.trajectory = parseTrajectory(text, path);
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("# ", 0) != 0) {
      if (!line.empty() && line[0] != '#') break;  // the header line: comments end
      continue;
    }
    const size_t colon = line.find(": ");
    if (colon == std::string::npos) continue;
    s.comments.emplace_back(line.substr(2, colon - 2), line.substr(colon + 2));
    s.header[s.comments.back().first] = s.comments.back().second;
  }
  if (!expected_brush_hash.empty()) {
    const auto it = s.header.find("brush_fnv1a64");
    if (it == s.header.end())
      s.warnings.push_back(path + ": no brush_fnv1a64 header: cannot check the brush");
    else if (it->second != expected_brush_hash)
      s.warnings.push_back(path + ": brush_fnv1a64 " + it->second +
                           " differs from the brush given (" + expected_brush_hash +
                           "): the session was recorded with another brush");
  }
  return s;
}

}  // namespace bristle::haptics
