#pragma once
// The engine's objects behind the public API's opaque types (include/bristle/),
// and the translation of the engine's errors into bristle::api::Error. For
// the API's own sources only: never installed.

#include <string>
#include <utility>

#include "bristle/brush.h"
#include "bristle/error.h"
#include "bristle/trajectory.h"
#include "engine/base/error.h"
#include "engine/model/brush.h"
#include "engine/model/trajectory.h"

namespace bristle::api {

struct Brush::Model {
  bristle::Brush brush;
  std::string path;
};

struct Trajectory::Model {
  bristle::Trajectory trajectory;
};

// The public category of an engine error's exit code.
ErrorCategory categoryOf(ExitCode code);

// Runs f, turning the engine's errors into the API's one type (same message,
// same category); an unexpected exception becomes kSoftware.
template <class F>
auto translateErrors(F&& f) -> decltype(f()) {
  try {
    return std::forward<F>(f)();
  } catch (const bristle::Error& e) {
    throw api::Error(categoryOf(e.code()), e.what());
  } catch (const api::Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    throw api::Error(ErrorCategory::kSoftware, oneLine(std::string("internal error: ") + e.what()));
  }
}

}  // namespace bristle::api
