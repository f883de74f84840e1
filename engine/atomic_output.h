#pragma once
// An output file that appears only when complete: it is written to a temporary
// file beside the target and renamed into place on commit(). A run that fails
// (or throws) before commit() leaves no partial file (ARCHITECTURE.md).
//
// An output is a new file or an existing regular file. Through a symbolic link
// to a regular file the link's target is replaced and the link kept; a
// directory, FIFO, device or socket (also behind a link) is refused, never
// replaced by a regular file.

#include <fstream>
#include <string>
#include <vector>

namespace bristle {

class AtomicOutput {
 public:
  // Throws bristle::Error(kCantCreate) when the temporary file cannot be created
  // or the target is not a regular file.
  explicit AtomicOutput(const std::string& path);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  std::ostream& stream() { return out_; }
  // Flushes, checks for write errors (kIoError) and renames into place.
  void commit();
  const std::string& path() const { return path_; }

 private:
  std::string path_, target_, tmp_;
  std::ofstream out_;
  bool committed_ = false;
};

// The file an output at `path` replaces: path itself, or the final target of
// the symbolic link it is. Throws kCantCreate ("is a FIFO; an output must be a
// regular file") when that exists and is not a regular file.
std::string outputTarget(const std::string& path);

// Throws kCantCreate when a file could not be created at path (checked by
// creating and removing a probe beside it), so long runs fail before they start.
void checkCanCreate(const std::string& path);

// A file on the command line and the option that names it ("-o", "--brush").
struct NamedFile {
  std::string option, path;
};

// Checks a command's outputs before anything is written: none is the same file
// as an input (kUsage; the same device and inode, through links too) or as
// another output (kUsage), and each is a new file or a regular file
// (outputTarget, kCantCreate). Empty paths are skipped.
void checkOutputs(const std::vector<NamedFile>& outputs, const std::vector<NamedFile>& inputs);

}  // namespace bristle
