#pragma once
// How long a batch job will take, roughly, so that a pool of several workers
// can start the longest first. A batch is as long as its last job: started in
// manifest order, the last long job (an S-curve, a painting) runs alone at
// the end while the other workers have nothing left (docs/PERFORMANCE.md,
// "Batch throughput"). Only the order of starting depends on this; the pixels
// and the outputs do not.

#include <limits>

#include "batch/manifest.h"

namespace bristle {

// A cost no estimate reaches: for jobs whose inputs cannot be read here (they
// fail fast on their own) or that are not estimated (sheets). They start first.
inline constexpr double kUnknownJobCost = std::numeric_limits<double>::infinity();

// The job's simulation work in spine-steps: for a stroke, the steps the
// render will plan (planStepTimes with the default simulation options) times
// the brush's spines; for a scene, the sum over its strokes; a preview, 1.
// Reads the job's brush, trajectory or scene; never throws.
double estimateJobCost(const BatchJob& job);

}  // namespace bristle
