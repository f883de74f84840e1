#pragma once
// Outputs that appear only when complete, and a run's outputs all together or
// none (docs/errors.md, "Outputs").
//
// An AtomicOutput is written to NAME.tmp-PID beside its target: the temporary
// file is created exclusively (O_CREAT | O_EXCL | O_NOFOLLOW, so a file or a
// symbolic link planted at that name is never written through), written,
// flushed to the disk (fsync), renamed over the target, and the folder is
// synced so that the rename survives a crash. A run that fails (or throws)
// before commit() leaves no partial file, and neither does a signal that ends
// the process (engine/base/temp_files.h).
//
// An output is a new name or an existing regular file; a symbolic link at the
// output's name is refused, never written through nor replaced (outputTarget).
//
// A CommitGroup makes a run's outputs one: while a group is open,
// AtomicOutput::commit() only finishes its file (written, synced) and
// hands it to the group; the group's commit() renames them all once every one
// was written, and a group destroyed without commit() removes every temporary
// file it holds. So when a run's last output fails, none of its outputs
// appears, and every file that existed before is untouched.

#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <streambuf>
#include <string>
#include <string_view>
#include <vector>

#include "engine/base/temp_files.h"

namespace bristle {

// A finished or unfinished temporary file and where it goes.
struct PendingOutput {
  std::string path, tmp;  // as named on the command line; its temporary file
  std::optional<TempFileRegistration> registration;
  ~PendingOutput();  // removes tmp unless it was renamed (tmp emptied)
};

class AtomicOutput {
 public:
  // Throws bristle::Error(kCantCreate) when the target is not a new name or a
  // regular file, or the temporary file cannot be created.
  explicit AtomicOutput(const std::string& path);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  std::ostream& stream() { return out_; }
  void write(std::string_view bytes) { out_.write(bytes.data(), std::streamsize(bytes.size())); }
  // Flushes and syncs the file (kIoError "PATH: write failed: WHY" when
  // writing failed), then renames it into place (kCantCreate), or hands it
  // to the open CommitGroup.
  void commit();
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::unique_ptr<PendingOutput> pending_;
  int fd_ = -1;  // the temporary file, written through buf_
  std::unique_ptr<std::streambuf> buf_;
  std::ostream out_{nullptr};
};

class CommitGroup {
 public:
  // Opens the group (inside another, it hands its outputs to that one on
  // commit()).
  CommitGroup();
  ~CommitGroup();  // removes the temporary files of a group not committed
  CommitGroup(const CommitGroup&) = delete;
  CommitGroup& operator=(const CommitGroup&) = delete;

  // Renames every output into place (each was written and synced already),
  // after checking that each target is still a new name or a regular file.
  // Throws kCantCreate, removing every temporary file left.
  void commit();
  // The open group, or nullptr.
  static CommitGroup* open();
  // Runs `last` after the renames of a successful commit() (inside another
  // group: after that one's): standard output, written only once every file
  // is in place, so that a run that fails writes nothing to it.
  void atCommit(std::function<void()> last);

 private:
  friend class AtomicOutput;
  std::vector<std::unique_ptr<PendingOutput>> pending_;
  std::vector<std::function<void()>> last_;
  CommitGroup* outer_;
};

// Writes bytes to path as one AtomicOutput (joining the open CommitGroup).
void writeFileAtomically(const std::string& path, std::string_view bytes);

// The file an output at `path` replaces: path itself. Throws kCantCreate when
// it exists and is not a regular file ("is a FIFO; an output must be a regular
// file", also for a symbolic link to one), or is a symbolic link to a regular
// file or to nothing ("is a symbolic link; ..."): an output is never written
// through a link, nor does it replace the link.
std::string outputTarget(const std::string& path);

// Throws kCantCreate when a file could not be created at path (checked by
// creating and removing a probe beside it), so long runs fail before they start.
void checkCanCreate(const std::string& path);

// Writes bytes to root/relative and never through a symbolic link, so a
// relative path stays beneath root (a batch's --out): every folder of
// `relative` is opened with O_NOFOLLOW beneath the one before (and created
// when missing), the file must be new or a regular file (not a link), and it
// is written as an AtomicOutput is (exclusive temporary file, fsync, rename,
// the folder synced). Throws
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
