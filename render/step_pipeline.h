#pragma once
// Simulation and drawing on two threads: the steps of
// a stroke are simulated on a second thread, up to kStepsAhead ahead, while the
// calling thread draws the footprint and moves the paint of the steps already
// solved. The simulation never reads the paint or the canvas, and the states
// reach the caller in the order they were solved, so the pixels are the same
// as when the two take turns on one thread (docs/PERFORMANCE.md, "Simulation
// and drawing on two threads").

#include "render/stroke_renderer.h"

namespace bristle::render {

// How many solved states may wait for the drawing thread. Four covers the
// jitter between a step's solve and its drawing; more only holds memory.
inline constexpr int kStepsAhead = 4;

// The threads a render uses when StrokeOptions::threads is 0: 2 where this
// process may run on two or more CPUs (its affinity mask, which taskset,
// cgroup cpusets and Slurm set), else 1.
int defaultRenderThreads();

// stepper.walk(trajectory, on_step) with the walk on a second thread and
// on_step on the calling thread, which owns the GL context (the engine starts
// no thread: docs/design.md, "Layers"). on_step sees the same states, steps
// and order. An exception from either side stops both: the stepping thread is
// joined before this returns or rethrows, and the stepper's simulation is left
// at the step it had reached (its stats stand).
void walkAhead(Stepper& stepper, const Trajectory& trajectory, const StepCallback& on_step);

}  // namespace bristle::render
