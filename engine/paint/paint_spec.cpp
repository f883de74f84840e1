#include "engine/paint/paint_spec.h"

#include "engine/model/canvas.h"
#include "engine/paint/pigments.h"

namespace bristle {

const char* paintModeName(PaintLoad::Mode mode) {
  switch (mode) {
    case PaintLoad::Mode::kSolid: return "solid";
    case PaintLoad::Mode::kAcross: return "across";
    case PaintLoad::Mode::kTip: return "tip";
  }
  return "?";
}

std::optional<PaintLoadProblem> checkPaintLoad(const PaintLoad& load,
                                               const std::string& mode_label) {
  size_t min_paints = 1, max_paints = 1;
  const char* order = "";
  if (load.mode == PaintLoad::Mode::kAcross) {
    min_paints = 2;
    max_paints = kMaxPaintsPerLoad;
    order = " (left to right across the brush)";
  } else if (load.mode == PaintLoad::Mode::kTip) {
    min_paints = max_paints = 2;
    order = " (body, then tip)";
  }
  if (load.paints.size() < min_paints || load.paints.size() > max_paints) {
    const std::string count = min_paints == max_paints ? std::to_string(min_paints)
                                                       : std::to_string(min_paints) + ".." +
                                                             std::to_string(max_paints);
    return PaintLoadProblem{"paints", mode_label + " takes " + count + " paint" +
                                          (max_paints > 1 ? "s" : "") + order};
  }
  for (size_t i = 0; i < load.paints.size(); ++i) {
    const std::string& name = load.paints[i];
    const std::string field = "paints/" + std::to_string(i);
    if (!name.empty() && name[0] == '#') {
      Rgb c;
      if (!parseHexColour(name, &c))
        return PaintLoadProblem{field, "colour '" + name +
                                           "' does not parse (must be #rrggbb, hex digits)"};
    } else if (!findPigment(name)) {
      return PaintLoadProblem{field, "unknown pigment '" + name + "' (known: " + pigmentNames() +
                                         "; or a colour \"#rrggbb\")"};
    }
  }
  if (!(load.amount > 0 && load.amount <= 1))
    return PaintLoadProblem{"amount",
                            "must be in (0, 1] (a fraction of the brush's paint capacity)"};
  if (!(load.tip_length > 0 && load.tip_length < 1))
    return PaintLoadProblem{"tip_length",
                            "must be in (0, 1) (a fraction of the hair length, from the tip)"};
  if (!(load.dilution >= 0 && load.dilution <= 1))
    return PaintLoadProblem{"dilution", "must be in [0, 1]"};
  return std::nullopt;
}

}  // namespace bristle
