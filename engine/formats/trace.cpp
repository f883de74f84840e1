#include "engine/formats/trace.h"

#include <nlohmann/json.hpp>

#include "engine/mechanics/spine_kinematics.h"

namespace bristle {
namespace {

nlohmann::json vec3(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

std::string traceLine(const BrushState& st) {
  nlohmann::json j;
  j["step"] = st.step;
  j["t_s"] = st.t_s;
  const Eigen::Quaterniond& q = st.handle.rotation;
  j["handle"] = {{"position_mm", vec3(st.handle.position_mm)},
                 {"quaternion_wxyz", {q.w(), q.x(), q.y(), q.z()}}};
  j["force_n"] = vec3(st.force_n);
  nlohmann::json spines = nlohmann::json::array();
  for (const SpineState& s : st.spines) {
    nlohmann::json js;
    nlohmann::json joints = nlohmann::json::array(), angles = nlohmann::json::array();
    for (const Eigen::Vector3d& x : s.joints_mm) joints.push_back(vec3(x));
    // eq. 10's (theta, phi) of each joint's axis relative to its parent.
    for (const Eigen::Matrix3d& r : s.rot) {
      const Eigen::Vector2d a = eulerAnglesOfAxis(r);
      angles.push_back({a[0], a[1]});
    }
    js["joints_mm"] = std::move(joints);
    js["angles_rad"] = std::move(angles);
    js["contact"] = s.contact;
    js["normal_force_n"] = s.solution.normal_force_n;
    js["sliding"] = s.sliding;
    // Where each sticking contact joint is held (SpineState::stuck_xy_mm);
    // null for a joint off the paper or sliding.
    nlohmann::json stuck = nlohmann::json::array();
    for (size_t k = 0; k < s.contact.size(); ++k) {
      const bool held = s.contact[k] && !s.sliding[k] && k < s.stuck_xy_mm.size();
      stuck.push_back(held ? nlohmann::json{s.stuck_xy_mm[k].x(), s.stuck_xy_mm[k].y()}
                           : nlohmann::json(nullptr));
    }
    js["stuck_xy_mm"] = std::move(stuck);
    js["energy_nmm"] = {{"spring", s.energy.spring_nmm},
                        {"friction", s.energy.friction_nmm},
                        {"damping", s.energy.damping_nmm},
                        {"volume", s.energy.volume_nmm},
                        {"cushion", s.energy.cushion_nmm}};
    js["solver"] = {{"status", toString(s.summary.status)},
                    {"iterations", s.summary.iterations}};
    if (!s.summary.message.empty() && !s.summary.usable())
      js["solver"]["message"] = s.summary.message;
    spines.push_back(std::move(js));
  }
  j["spines"] = std::move(spines);
  return j.dump();
}

}  // namespace bristle
