// Linked into the test programs that solve in process: the process-wide
// set-up the command line does (process/process_hooks.h), made while the
// program starts, before Catch2's own main (Catch2::Catch2WithMain, prebuilt
// by Debian) runs a test, so that their solves are the CLI's bit for bit.

#include "process/process_hooks.h"

namespace {

[[maybe_unused]] const bool kProcessHooksInstalled = (bristle::installProcessHooks(), true);

}  // namespace
