#pragma once
// What a scene says about paint, as plain data (the scene reader fills it, the
// paint model in engine/paint/paint*.h acts on it). The paint model follows the paper's
// painting system (dAb, IMPaSTo): paint is a texture on the brush, moved both ways
// between brush and canvas through the footprint.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace bristle {

// How a brush is loaded before a stroke.
struct PaintLoad {
  enum class Mode {
    kSolid,   // one paint everywhere
    kAcross,  // 2-3 paints side by side across the brush's width axis (One-Stroke)
    kTip,     // paints[0] in the body, paints[1] on the last tip_length of the hairs
  };
  Mode mode = Mode::kSolid;
  // Each a pigment name from the pigment table ("ultramarine", "cadmium-yellow",
  // ...) or a colour "#rrggbb" (an opaque paint of that colour).
  std::vector<std::string> paints;
  double amount = 1.0;      // fraction of the brush's paint_capacity, in (0, 1]
  double tip_length = 0.3;  // kTip: fraction of the hair length, from the tip
  // Thinner paint (more medium) flows more freely and covers less: in [0, 1].
  double dilution = 0.0;
};

inline constexpr int kMaxPaintsPerLoad = 3;  // "across": 2-3 paints side by side

// "solid", "across", "tip": the mode's name in scenes and on the command line.
const char* paintModeName(PaintLoad::Mode mode);

// A rule of a paint load broken: the field ("paints", "paints/1", "amount",
// "tip_length", "dilution") and the rule, for the caller to name the place (a
// JSON pointer, an option).
struct PaintLoadProblem {
  std::string field;
  std::string rule;
};

// The one set of rules for a paint load, wherever it comes from (a scene's or a
// sheet's "paint", the command line's --paint, --load, --amount and
// --tip-length, BrushPaint::load): a paint count for the mode (solid 1, across
// 2-3, tip 2: body, then tip), each paint a pigment of the table or "#rrggbb",
// amount in (0, 1], tip_length in (0, 1) (at 0 or 1 a tip load is a solid load of
// one of its paints), dilution in [0, 1]. The first rule broken, in that order,
// or nothing. `mode_label` names the mode in the count's rule (`mode "tip"`,
// `--load tip`).
std::optional<PaintLoadProblem> checkPaintLoad(const PaintLoad& load,
                                               const std::string& mode_label);

// The paper's colour wherever none is given: a scene's "background", a sheet's,
// and the command line's --background. One definition, so that the same stroke
// drawn as a one-stroke scene, a sheet cell or a render lands on the same paper.
inline constexpr const char* kDefaultPaperColour = "#f6f1e6";

// The paper's surface: a seeded height field that decides contact where the
// brush barely touches (dry brush catches only the tooth).
struct PaperSpec {
  std::string colour = kDefaultPaperColour;
  double tooth_depth_mm = 0.03;  // peak-to-valley height of the grain
  double tooth_scale_mm = 0.4;   // feature size of the grain
  std::uint64_t seed = 1;
};

// How pigments combine on the canvas and on the brush.
enum class MixModel {
  kKubelkaMunk,  // K and S per channel, layers composited (the default)
  kLinearRgb,    // linear-light RGB averaging (fallback, for comparison)
};

}  // namespace bristle
