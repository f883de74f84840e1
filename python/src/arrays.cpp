// Brush and Trajectory (bristle/brush.h, bristle/trajectory.h), and images
// out as numpy arrays.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "bindings.h"
#include "bristle/brush.h"
#include "bristle/trajectory.h"

namespace bristle::py_module {

namespace {

// Rows of an N x K float64 array (checked N x K by the package) as the API's arrays.
template <size_t K>
std::vector<std::array<double, K>> rowsOf(const DoubleArray& a) {
  const auto v = a.unchecked<2>();
  std::vector<std::array<double, K>> rows(static_cast<size_t>(v.shape(0)));
  for (py::ssize_t i = 0; i < v.shape(0); ++i)
    for (size_t k = 0; k < K; ++k) rows[i][k] = v(i, static_cast<py::ssize_t>(k));
  return rows;
}

std::vector<double> valuesOf(const DoubleArray& a) {
  return std::vector<double>(a.data(), a.data() + a.size());
}

api::Brush loadBrush(const py::object& name_or_path) {
  // A library name as str, or a path (str or os.PathLike).
  const bool pathlike = py::isinstance<py::str>(name_or_path) ||
                        py::hasattr(name_or_path, "__fspath__");
  if (!pathlike)
    usageError("Brush: name_or_path: must be a str (a library name such as 'round') or a "
               "path, not " + std::string(py::str(name_or_path.get_type().attr("__name__"))));
  const py::object path = py::module_::import("os").attr("fspath")(name_or_path);
  if (!py::isinstance<py::str>(path)) usageError("Brush: name_or_path: a path must be a str");
  return api::Brush::load(path.cast<std::string>());
}

void bindBrush(py::module_& m) {
  py::class_<api::Brush>(m, "Brush", R"(A brush of the library, or a bristle-brush/1 file.

Brush("round") looks the name up in the brush library (the install's
share/bristle/brushes, then BRISTLE_BRUSH_PATH); a str containing '/' or
ending in .json, or an os.PathLike, is a file. Immutable; cheap to share.)")
      .def(py::init(&loadBrush), py::arg("name_or_path"))
      .def_property_readonly("name", &api::Brush::name, "the file's \"name\"")
      .def_property_readonly("path", &api::Brush::path, "the file it was read from")
      .def_property_readonly("spine_count", &api::Brush::spineCount, "spines (hair tufts)")
      .def_property_readonly("hair_length_mm", &api::Brush::hairLengthMm,
                             "longest spine, root to tip (mm)")
      .def_property_readonly("reach_mm", &api::Brush::reachMm,
                             "furthest any hair reaches from the ferrule centre (mm)")
      .def("__repr__", [](const api::Brush& b) {
        return "bristle.Brush('" + b.name() + "', spine_count=" + std::to_string(b.spineCount()) +
               ")";
      });
  m.def("set_brush_library_dirs", &api::setBrushLibraryDirs, py::arg("dirs"),
        "The folders a brush name is looked up in, in order, for the whole process.");
}

void bindTrajectory(py::module_& m) {
  py::class_<api::Trajectory>(m, "Trajectory")
      .def_static(
          "load", [](const std::string& path) { return api::Trajectory::load(path); },
          py::arg("path"))
      .def_static(
          "load_for",
          [](const std::string& path, const api::Brush& brush) {
            std::vector<std::string> warnings;
            api::Trajectory t = api::Trajectory::load(path, brush, &warnings);
            return std::make_pair(std::move(t), std::move(warnings));
          },
          py::arg("path"), py::arg("brush"))
      .def_static("from_arrays",
                  [](const DoubleArray& t, const DoubleArray& xyz, const DoubleArray& q) {
                    return api::Trajectory::fromArrays(valuesOf(t), rowsOf<3>(xyz), rowsOf<4>(q));
                  })
      .def_static("from_depth",
                  [](const DoubleArray& t, const DoubleArray& xy, const DoubleArray& depth,
                     const DoubleArray& q) {
                    return api::Trajectory::fromArraysWithDepth(valuesOf(t), rowsOf<2>(xy),
                                                                valuesOf(depth), rowsOf<4>(q));
                  })
      .def_property_readonly("sample_count", &api::Trajectory::sampleCount)
      .def_property_readonly("start_s", &api::Trajectory::startS)
      .def_property_readonly("end_s", &api::Trajectory::endS)
      .def_property_readonly("has_depths", &api::Trajectory::hasDepths);
}

}  // namespace

py::array imageArray(api::Image&& image) {
  auto* pixels = new std::vector<std::uint8_t>(std::move(image.pixels));
  const py::capsule owner(pixels, [](void* p) { delete static_cast<std::vector<std::uint8_t>*>(p); });
  const py::ssize_t h = image.height_px, w = image.width_px, c = image.channels;
  return py::array_t<std::uint8_t>({h, w, c}, {w * c, c, py::ssize_t{1}}, pixels->data(), owner);
}

void bindBrushAndTrajectory(py::module_& m) {
  bindBrush(m);
  bindTrajectory(m);
}

}  // namespace bristle::py_module
