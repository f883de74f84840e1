// _bristle: the extension module behind `import bristle` (docs/python.md).
#include <pybind11/pybind11.h>

#include "bindings.h"
#include "bristle/version.h"
#include "engine/solvers/ipopt/ipopt_timers.h"
#include "process/getrusage_hook.h"
#include "process/process_hooks.h"

PYBIND11_MODULE(_bristle, m) {
  namespace pm = bristle::py_module;
  m.doc() = "bristle's public C++ API (docs/api.md) for the package bristle";
  // The command line's process-wide set-up (docs/api.md, "Process-wide
  // set-up"): bristle's dense KKT solver as Ipopt's MA27, for the command
  // line's optima bit for bit and its speed.
  bristle::installProcessHooks();
  // Ipopt 3.11's timers make ~155,000 getrusage system calls per data-set
  // stroke, a fifth of its CPU, and their per-process lock costs the threads'
  // scaling (docs/PERFORMANCE.md, "The Python module"): libipopt's slot goes
  // to bristle's rule (process/getrusage_hook.h). False: not found, the
  // solves are the same, only slower.
  m.attr("_timers_patched") = bristle::routeIpoptGetrusage();
  m.def("_route_ipopt_getrusage", &bristle::routeIpoptGetrusage, pybind11::arg("through_rule"),
        "Routes libipopt's getrusage to bristle's rule (True) or back to the C "
        "library's (False), between solves; True when a slot was written (benchmarks)");
  m.def("_ipopt_clock_read_skipped", &bristle::ipoptClockReadSkipped,
        "Whether Ipopt's own CPU clock, read inside a solve's scope, came to "
        "bristle's getrusage rule without a system call (tests)");
  m.attr("__version__") = bristle::kVersion;
  pm::bindErrors(m);
  pm::bindBrushAndTrajectory(m);
  pm::bindRender(m);
  pm::bindSimulation(m);
}
