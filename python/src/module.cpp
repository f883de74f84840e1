// _bristle: the extension module behind `import bristle` (docs/python.md).
#include <pybind11/pybind11.h>

#include "bindings.h"
#include "bristle/version.h"
#include "process/process_hooks.h"

PYBIND11_MODULE(_bristle, m) {
  namespace pm = bristle::py_module;
  m.doc() = "bristle's public C++ API (docs/api.md) for the package bristle";
  // The command line's process-wide set-up (docs/api.md, "Process-wide
  // set-up"): bristle's dense KKT solver as Ipopt's MA27, for the command
  // line's optima bit for bit and its speed.
  bristle::installProcessHooks();
  m.attr("__version__") = bristle::kVersion;
  pm::bindErrors(m);
  pm::bindBrushAndTrajectory(m);
  pm::bindRender(m);
  pm::bindSimulation(m);
}
