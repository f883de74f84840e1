#pragma once
// The per-step trace (`--trace FILE.jsonl`): one JSON object per simulation step
// with the keys fixed in docs/design.md, "Formats" (described in docs/formats.md,
// "Trace"). Tests and people read it.

#include <string>

#include "engine/dynamics/simulation.h"

namespace bristle {

// One line of JSON (no trailing newline) describing the state after a step.
std::string traceLine(const BrushState& state);

}  // namespace bristle
