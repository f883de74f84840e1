// Fuzz target: a recorded session as replay reads it (a trajectory with
// buttons, forces and "# key: value" header lines; a last line cut off is
// dropped with a warning). The input is a memory file: loadSession takes a path.

#include "fuzz/fuzz_input.h"
#include "haptics/session_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const bristle::fuzz::MemoryFile file(data, size);
  try {
    // Warnings may quote the file's bytes: the CLI prints them through
    // printError, which shows control characters as \u escapes (\u000a).
    (void)bristle::haptics::loadSession(file.path(), "0123456789abcdef");
  } catch (const bristle::Error& e) {
    bristle::fuzz::checkRefusal(e);
  }
  return 0;
}
