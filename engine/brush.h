#pragma once
// Brush description, JSON format `bristle-brush/1` (ARCHITECTURE.md, "Formats";
// docs/brush-format.md). A brush is a few simulated spines (paper §3) in the
// brush frame: origin at the ferrule mouth, hairs hanging along -z at rest.

#include <Eigen/Core>
#include <string>
#include <vector>

namespace bristle {

// Limits that keep a brush file from asking for absurd work.
inline constexpr int kMaxSpines = 64;
inline constexpr int kMaxJointsPerSpine = 16;

struct SpineSpec {
  Eigen::Vector3d root_mm = Eigen::Vector3d::Zero();  // in the brush frame
  // Joint i (0-based) bends segment i relative to its parent (segment i-1, or
  // the ferrule for i = 0). All per-joint arrays have one entry per segment.
  std::vector<double> segment_lengths_mm;
  std::vector<double> stiffness_nmm_per_rad;  // K_i, eq. 2
  std::vector<double> damping_nmm;            // D_i, eq. 4 (joint friction torque)
  std::vector<Eigen::Vector2d> rest_angles_rad;  // (theta, phi) of the unloaded joint
  // Footprint strip width at the root and at the end of each segment (n + 1).
  std::vector<double> width_mm;

  int jointCount() const { return static_cast<int>(segment_lengths_mm.size()); }
  double lengthMm() const;
};

struct FrictionSpec {
  double mu_static = 0.4;    // used while a contact joint sticks (§3.4.1)
  double mu_kinetic = 0.35;  // used while it slides
  double anisotropy_strength = 0;  // C_eta of eq. 14, in [0, 1]
  double anisotropy_exponent = 2;  // k of eq. 14, >= 1
};

struct Brush {
  std::string path;  // for messages
  std::string name;
  std::string description;
  std::vector<SpineSpec> spines;
  FrictionSpec friction;
  double paint_capacity = 1.0;  // relative amount of paint the brush holds

  // Largest distance from the ferrule centre any hair can reach (mm).
  double reachMm() const;
};

// Parses and validates; throws bristle::Error (66 missing, 65 bad data naming the
// JSON pointer and the rule).
Brush loadBrush(const std::string& path);
Brush parseBrush(const std::string& text, const std::string& path_for_messages);

}  // namespace bristle
