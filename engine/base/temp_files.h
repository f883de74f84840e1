#pragma once
// Temporary files removed when a signal stops the process: SIGINT, SIGTERM,
// SIGHUP and every other catchable signal whose default action ends it
// (docs/errors.md, "Outputs"). Every output is written to NAME.tmp-PID and
// renamed into place when complete; a run that fails removes it in its
// destructor, but a signal's default action ends the process without running
// any. The handler installed here unlinks every registered temporary file, then
// the signal's default action ends the process, so the exit status still says
// which signal it was.
//
// The registry is a table of paths that grows by fixed chunks: registering
// copies the path into a free slot before the file is created, and the handler
// only reads slots and calls unlink(2), which is async-signal-safe.

#include <atomic>
#include <string>

namespace bristle {

// Installs the handler for those signals (again after a command that handled
// SIGINT and SIGTERM itself, e.g. `record` during the live session).
void installTempFileCleanup();

// A temporary file's registration, for as long as it lives: register before
// creating the file, and keep it until the file is renamed or removed.
class TempFileRegistration {
 public:
  explicit TempFileRegistration(const std::string& path);
  ~TempFileRegistration();
  TempFileRegistration(const TempFileRegistration&) = delete;
  TempFileRegistration& operator=(const TempFileRegistration&) = delete;

 private:
  std::atomic<int>* slot_ = nullptr;  // its slot's state; null for a path over PATH_MAX
};

}  // namespace bristle
