// Simulation (bristle/simulation.h): a brush stepped by the caller, its state
// as numpy arrays. Spines may have different numbers of joints; the joint
// arrays are padded to the longest with NaN (positions) and False (contact).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <array>
#include <limits>
#include <mutex>

#include "bindings.h"
#include "bristle/simulation.h"

namespace bristle::py_module {

namespace {

api::Pose poseOf(const DoubleArray& xyz_mm, const DoubleArray& q_wxyz) {
  api::Pose pose;
  std::copy_n(xyz_mm.data(), 3, pose.xyz_mm.begin());
  std::copy_n(q_wxyz.data(), 4, pose.quaternion_wxyz.begin());
  return pose;
}

py::array_t<double> vector3(const std::array<double, 3>& v) {
  py::array_t<double> a(3);
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

// joints_mm (S x J x 3, root first), contact (S x J, the root never), spine
// forces (S x 3), solved (S).
py::dict spineArrays(const api::StepResult& s) {
  const py::ssize_t spines = static_cast<py::ssize_t>(s.spines.size());
  size_t longest = 0;
  for (const api::SpineState& sp : s.spines) longest = std::max(longest, sp.joints_mm.size());
  const py::ssize_t joints = static_cast<py::ssize_t>(longest);
  py::array_t<double> xyz({spines, joints, py::ssize_t{3}});
  py::array_t<bool> contact({spines, joints});
  py::array_t<double> force({spines, py::ssize_t{3}});
  py::array_t<bool> solved(spines);
  auto x = xyz.mutable_unchecked<3>();
  auto c = contact.mutable_unchecked<2>();
  auto f = force.mutable_unchecked<2>();
  auto ok = solved.mutable_unchecked<1>();
  for (py::ssize_t i = 0; i < spines; ++i) {
    const api::SpineState& sp = s.spines[static_cast<size_t>(i)];
    for (py::ssize_t j = 0; j < joints; ++j) {
      const bool has = static_cast<size_t>(j) < sp.joints_mm.size();
      for (py::ssize_t k = 0; k < 3; ++k)
        x(i, j, k) = has ? sp.joints_mm[j][k] : std::numeric_limits<double>::quiet_NaN();
      // contact[k] is joint k + 1's: the root is held by the ferrule.
      c(i, j) = j > 0 && static_cast<size_t>(j - 1) < sp.contact.size() && sp.contact[j - 1];
    }
    for (py::ssize_t k = 0; k < 3; ++k) f(i, k) = sp.force_n[k];
    ok(i) = sp.solved;
  }
  py::dict d;
  d["joints_mm"] = xyz;
  d["contact"] = contact;
  d["spine_force_n"] = force;
  d["solved"] = solved;
  return d;
}

py::dict stateDict(const api::StepResult& s) {
  py::dict d = spineArrays(s);
  d["t_s"] = s.t_s;
  d["force_n"] = vector3(s.force_n);
  d["contact_joints"] = s.contact_joints;
  return d;
}

struct LockedSimulation {
  std::mutex mutex;
  api::Simulation sim;
  LockedSimulation(const api::Brush& brush, api::Solver solver, int max_iterations)
      : sim(brush, solver, max_iterations) {}
};

py::dict step(LockedSimulation& s, const DoubleArray& xyz_mm, const DoubleArray& q_wxyz,
              double t_s) {
  const api::Pose pose = poseOf(xyz_mm, q_wxyz);
  {
    py::gil_scoped_release unlocked;
    const std::lock_guard<std::mutex> lock(s.mutex);
    s.sim.step(pose, t_s);
  }
  const std::lock_guard<std::mutex> lock(s.mutex);
  return stateDict(s.sim.state());
}

py::dict reset(LockedSimulation& s, const DoubleArray& xyz_mm, const DoubleArray& q_wxyz,
               double t_s) {
  const api::Pose pose = poseOf(xyz_mm, q_wxyz);
  const std::lock_guard<std::mutex> lock(s.mutex);
  s.sim.reset(pose, t_s);
  return stateDict(s.sim.state());
}

}  // namespace

void bindSimulation(py::module_& m) {
  py::enum_<api::Solver>(m, "Solver")
      .value("ipopt", api::Solver::kIpopt)
      .value("slsqp", api::Solver::kSlsqp);
  py::class_<LockedSimulation>(m, "Simulation")
      .def(py::init<const api::Brush&, api::Solver, int>())
      .def("step", &step)
      .def("reset", &reset)
      .def("state", [](LockedSimulation& s) {
        const std::lock_guard<std::mutex> lock(s.mutex);
        return stateDict(s.sim.state());
      });
}

}  // namespace bristle::py_module
