#pragma once
// Live sessions on disk. A session is a `bristle-trajectory/1` CSV with the
// optional buttons and fx_n,fy_n,fz_n columns (docs/formats.md, "Session"),
// written as it goes: line-buffered, and flushed at least every 100 ms, so a
// killed process loses at most the last 100 ms and leaves a file that replays
// up to its last complete line. Header comments record the device model, the
// servo rate, the units, the brush and its hash (FNV-1a 64 of the brush file's
// bytes, hex), which replay checks, and the options of the session's render
// (cli/session_render.h), which replay renders with.

#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "engine/model/trajectory.h"
#include "haptics/servo_loop.h"

namespace bristle::haptics {

// Hash of a brush file as sessions record it: hex64 of fnv1a64
// (engine/base/fnv1a64.h) of its bytes; throws kNoInput if unreadable.
std::string brushFileHash(const std::string& brush_path);

struct SessionHeader {
  std::string device_model;
  double servo_rate_hz = 1000;
  double session_rate_hz = 100;
  std::string brush_path;
  std::string brush_hash;  // hex of fnv1a64
  // "# KEY: VALUE" lines after the brush's, in order (a key may repeat); a
  // value must hold no line break.
  std::vector<std::pair<std::string, std::string>> options;
};

// Appends servo samples to a session file (decimated to the session rate)
// and, optionally, every sample to a force log `t_s,fx_n,fy_n,fz_n`.
class SessionWriter {
 public:
  // Throws kCantCreate naming the file.
  SessionWriter(const std::string& session_path, const std::string& forces_path,
                const SessionHeader& header);
  ~SessionWriter();
  SessionWriter(const SessionWriter&) = delete;
  SessionWriter& operator=(const SessionWriter&) = delete;

  void add(const ServoSample& s);
  // Flushes both files if the last flush is more than 50 ms old (wall clock).
  void flushIfDue();
  // Flushes, fsyncs and closes; throws kIoError if a write failed.
  void close();
  long sessionRows() const { return rows_; }
  long forceRows() const { return force_rows_; }

 private:
  std::FILE* open(const std::string& path);
  std::string session_path_, forces_path_;
  std::FILE* session_ = nullptr;
  std::FILE* forces_ = nullptr;
  std::uint64_t decimation_ = 10;
  std::int64_t last_flush_ns_ = 0;
  long rows_ = 0, force_rows_ = 0;
  double last_t_s_ = -1;
};

struct Session {
  Trajectory trajectory;
  std::map<std::string, std::string> header;  // "# key: value" comment lines (the last of a key)
  std::vector<std::pair<std::string, std::string>> comments;  // all of them, in order
  std::vector<std::string> warnings;          // one line each, for the user
};

// Reads a session for replay. A last line cut off mid-way (a crash) is dropped
// with a warning; everything else must parse (kDataError naming the line).
// expected_brush_hash (if not empty) is compared with the header's: a
// mismatch is a warning, not an error.
Session loadSession(const std::string& path, const std::string& expected_brush_hash = "");

}  // namespace bristle::haptics
