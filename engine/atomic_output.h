#pragma once
// An output file that appears only when complete: it is written to a temporary
// file beside the target and renamed into place on commit(). A run that fails
// (or throws) before commit() leaves no partial file (ARCHITECTURE.md).

#include <fstream>
#include <string>

namespace bristle {

class AtomicOutput {
 public:
  // Throws bristle::Error(kCantCreate) when the temporary file cannot be created.
  explicit AtomicOutput(const std::string& path);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  std::ostream& stream() { return out_; }
  // Flushes, checks for write errors (kIoError) and renames into place.
  void commit();
  const std::string& path() const { return path_; }

 private:
  std::string path_, tmp_;
  std::ofstream out_;
  bool committed_ = false;
};

// Throws kCantCreate when a file could not be created at path (checked by
// creating and removing a probe beside it), so long runs fail before they start.
void checkCanCreate(const std::string& path);

}  // namespace bristle
