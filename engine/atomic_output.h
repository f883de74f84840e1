#pragma once
// An output file that appears only when complete: it is written to a temporary
// file beside the target and renamed into place on commit(). A run that fails
// (or throws) before commit() leaves no partial file (docs/design.md, "Atomic
// output"), and neither does SIGINT or SIGTERM (engine/temp_files.h).
//
// An output is a new file or an existing regular file. Through a symbolic link
// to a regular file the link's target is replaced and the link kept; a
// directory, FIFO, device or socket (also behind a link) is refused, never
// replaced by a regular file.

#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "engine/temp_files.h"

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
  // Removes tmp_ when a signal stops the process (engine/temp_files.h).
  std::optional<TempFileRegistration> registration_;
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

// Writes bytes to root/relative and never through a symbolic link, so a
// relative path stays beneath root (a batch's --out): every folder of
// `relative` is opened with O_NOFOLLOW beneath the one before (and created
// when missing), the file must be new or a regular file (not a link), and it
// is written to a temporary file beside it and renamed into place. Throws
// kCantCreate naming root/relative and the link; kIoError when writing fails.
void writeFileBeneath(const std::string& root, const std::string& relative,
                      const std::string& bytes);
// Moves the file `from` to root/relative with writeFileBeneath's checks: a
// rename when both are on one file system (a batch's private folder is beneath
// --out), else a copy written as writeFileBeneath writes. `from` is gone after.
void moveFileBeneath(const std::string& from, const std::string& root,
                     const std::string& relative);
// writeFileBeneath's checks, creating nothing (a missing folder is fine).
void checkBeneath(const std::string& root, const std::string& relative);

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
