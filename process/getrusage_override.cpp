// getrusage(2) for a bristle program: the executable's definition comes first
// when the dynamic linker binds libipopt's reference to getrusage, so this
// takes the C library's place for the whole process, with bristle's one rule
// for it (process/getrusage_hook.h). Linked only into programs
// (process/process_hooks.h); the Python module routes libipopt's slot instead.

#include "process/getrusage_hook.h"

extern "C" int getrusage(int who, struct rusage* usage) noexcept {
  return bristle::timerAwareGetrusage(who, usage);
}
