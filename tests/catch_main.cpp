// The main of the test programs that solve in process: the process-wide
// set-up the command line does (process/process_hooks.h), so that their
// solves are the CLI's bit for bit, then Catch2's own session.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include "process/process_hooks.h"

int main(int argc, char** argv) {
  bristle::installProcessHooks();
  return Catch::Session().run(argc, argv);
}
