#pragma once
// The parts of the extension module _bristle (python/, docs/python.md), each
// binding one corner of the public C++ API (include/bristle/, docs/api.md).
// The package bristle (python/bristle/__init__.py) checks argument types and
// shapes and gives the user-facing names; these take what it passes.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <string>
#include <vector>

#include "bristle/error.h"
#include "bristle/render.h"

namespace bristle::py_module {

namespace py = pybind11;

// A C-contiguous float64 array, converted from any real dtype by the caller's checks.
using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

void bindErrors(py::module_& m);
void bindBrushAndTrajectory(py::module_& m);
void bindRender(py::module_& m);
void bindSimulation(py::module_& m);

// An image as an H x W x C uint8 numpy array that owns the image's pixel buffer
// (moved, not copied; freed with the array).
py::array imageArray(api::Image&& image);

// Raises bristle.Error with the message and exit code (the category follows).
[[noreturn]] void usageError(const std::string& message);

}  // namespace bristle::py_module
