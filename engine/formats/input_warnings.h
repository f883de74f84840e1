#pragma once
// Inputs that every rule accepts but that are almost surely a mistake, each
// told in one line (docs/errors.md, "Warnings"): the command goes on, since
// the input may be meant, but a user who did not mean it learns why before a
// long run rather than after it.

#include <string>

#include "engine/model/brush.h"
#include "engine/dynamics/simulation.h"
#include "engine/model/trajectory.h"

namespace bristle {

// A trajectory longer than this (s): a stroke lasts seconds and a recorded
// session minutes, while a stroke of a few seconds written in milliseconds
// (t_s 0..5350) spans an hour and a half.
inline constexpr double kLongTrajectoryS = 600;
// More planned simulation steps than this: over an hour of solving at the
// few milliseconds a step takes (docs/PERFORMANCE.md, "Per step: Ipopt and
// SLSQP").
inline constexpr double kManyPlannedSteps = 1e6;
// A brush whose spines and surface cage differ in size by more than this
// factor: the two are drawn from one set of hairs, so they agree within a
// factor of 1.2 in every brush of the library, while a brush in metres with
// its surface in millimetres is 1000 times off.
inline constexpr double kBrushPartsMaxRatio = 10;

// "FILE: t_s spans 5350 s (89 min); were the times in milliseconds?" when the
// trajectory lasts over kLongTrajectoryS, else, when `planned_steps` (its
// plannedStepCount with `options`; 0 when no brush is known) is over
// kManyPlannedSteps, a line naming the count and what makes it; else "".
std::string trajectoryWarning(const Trajectory& trajectory, double planned_steps,
                              const Brush* brush, const SimOptions& options);

// "FILE: /spines span ... mm but /surface/cage_vertices_mm ... mm ..." when the
// spines (their roots and their tips held straight down) and the surface's
// control cage differ in size by more than kBrushPartsMaxRatio; else "".
std::string brushScaleWarning(const Brush& brush);

}  // namespace bristle
