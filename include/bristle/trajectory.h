#pragma once
// bristle/trajectory.h -- the motion of a brush's handle: a bristle-trajectory/1
// CSV file (docs/formats.md, "Trajectory"), or arrays built in memory.
//
// Poses are the ferrule's: position in canvas mm (x right, y up, z above the
// paper), rotation as a unit quaternion w, x, y, z (any non-zero scale is
// normalised). Times in seconds, strictly increasing.

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace bristle::api {

class Brush;

class Trajectory {
 public:
  using Quaternions = std::vector<std::array<double, 4>>;  // w, x, y, z each

  // A bristle-trajectory/1 CSV file. Throws Error: kNoInput when missing,
  // kDataError naming the line, column and rule.
  static Trajectory load(const std::string& path);

  // What `bristle render --trajectory FILE` reads for `brush`: a
  // bristle-trajectory/1 file as load(path) reads it, or a pen recording
  // (MyPaint events, a Pointer Events CSV, an SVG's paths; docs/input.md)
  // imported with bristle import's default mapping for this brush, so the
  // same file gives the same pixels as the command line. What the import
  // notes (samples merged, SVG elements skipped) is appended to *warnings
  // when given. Throws Error as load(path) does.
  static Trajectory load(const std::string& path, const Brush& brush,
                         std::vector<std::string>* warnings = nullptr);

  // From arrays of equal length (at least 2 samples): t_s[i], the ferrule at
  // xyz_mm[i], rotated by quaternion_wxyz[i]. Throws Error (kDataError) naming
  // the argument, the sample and the rule: NaN or infinity, positions beyond
  // +-100000 mm, times beyond +-1e9 s, times that do not increase strictly, a
  // quaternion of (near) zero norm or a component beyond +-1e6.
  static Trajectory fromArrays(const std::vector<double>& t_s,
                               const std::vector<std::array<double, 3>>& xyz_mm,
                               const std::vector<std::array<double, 4>>& quaternion_wxyz);

  // The same with heights given as press depth past the brush's first contact
  // (depth_mm[i]: positive into the paper): x, y from xy_mm, z found for the
  // brush the trajectory is rendered or simulated with (docs/formats.md,
  // "Heights relative to the paper").
  static Trajectory fromArraysWithDepth(const std::vector<double>& t_s,
                                        const std::vector<std::array<double, 2>>& xy_mm,
                                        const std::vector<double>& depth_mm,
                                        const std::vector<std::array<double, 4>>& quaternion_wxyz);

  std::size_t sampleCount() const;
  double startS() const;
  double endS() const;
  bool hasDepths() const;  // heights wait for a brush (fromArraysWithDepth, a depth_mm column)

  struct Model;  // the engine's trajectory, for the API's own sources
  const Model& model() const { return *model_; }

 private:
  explicit Trajectory(std::shared_ptr<const Model> model) : model_(std::move(model)) {}
  std::shared_ptr<const Model> model_;
};

}  // namespace bristle::api
