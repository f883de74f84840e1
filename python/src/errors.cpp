#include <pybind11/pybind11.h>

#include <exception>
#include <string>

#include "bindings.h"

namespace bristle::py_module {

namespace {

// bristle.Error, the package's exception class (python/bristle/__init__.py),
// handed over at import. Kept for the life of the process: the translator may
// run until the interpreter ends, so it is never destroyed.
py::object* g_error_class = nullptr;

void raiseBristleError(const char* message, int exit_code) {
  if (g_error_class == nullptr) {
    PyErr_SetString(PyExc_RuntimeError, message);
    return;
  }
  const py::object error = (*g_error_class)(message, exit_code);
  PyErr_SetObject(g_error_class->ptr(), error.ptr());
}

}  // namespace

void usageError(const std::string& message) {
  throw api::Error(api::ErrorCategory::kUsage, message);
}

void bindErrors(py::module_& m) {
  m.def(
      "_set_error_class",
      [](py::object cls) {
        if (g_error_class == nullptr) g_error_class = new py::object();
        *g_error_class = std::move(cls);
      },
      "The exception class every bristle::api::Error becomes (bristle.Error).");
  // The public API's one exception (bristle/error.h) keeps its message and
  // exit code; std::bad_alloc stays pybind11's MemoryError.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const api::Error& e) {
      raiseBristleError(e.what(), e.exitCode());
    }
  });
}

}  // namespace bristle::py_module
