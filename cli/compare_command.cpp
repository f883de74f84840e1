// `bristle compare A B`: are two PNGs the same picture, and if not, by how much
// do they differ against a tolerance (render/image/image_compare.h). Exit 0 within
// tolerance, 1 not (also for images of different sizes); --json prints one
// object with every metric, the tolerance and the verdict. --align canvas
// compares two renders where their canvases overlap, by the placement the
// renderer writes into each PNG (bristle:canvas), so that renders of one
// stroke on canvases of different extent compare.

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "cli/commands.h"
#include "cli/options.h"
#include "cli/inputs.h"
#include "engine/base/atomic_output.h"
#include "engine/base/error.h"
#include "engine/base/fnv1a64.h"
#include "engine/base/text_file.h"
#include "render/image/image_compare.h"
#include "render/image/png_io.h"

namespace bristle::cli {
namespace {

using render::CompareTolerance;
using render::ImageComparison;
using render::ToleranceCheck;

std::string formatName(const render::PngFormat& f) {
  static constexpr const char* kLayout[] = {"grey", "grey+alpha", "RGB", "RGBA"};
  return std::to_string(f.bit_depth) + "-bit " + kLayout[f.channels - 1];
}

// The preset, with the limits given on the command line put in.
CompareTolerance toleranceOf(const CompareArgs& args) {
  const bool custom = !std::isnan(args.max_abs) || !std::isnan(args.pixel_threshold) ||
                      !std::isnan(args.max_percent_over) || !std::isnan(args.min_ssim) ||
                      !std::isnan(args.min_psnr_db);
  CompareTolerance t;
  if (!args.tolerance.empty()) {
    t = render::tolerancePreset(args.tolerance);
    if (custom && t.require_identical) {
      throw Error(ExitCode::kUsage,
                  "compare: --tolerance exact takes no limits (it requires equal pixels)");
    }
    if (custom) t.name += "+custom";
  } else if (custom) {
    t.name = "custom";
  } else {
    t = render::tolerancePreset("exact");
  }
  if (!std::isnan(args.max_abs)) t.max_abs = args.max_abs;
  if (!std::isnan(args.pixel_threshold)) t.pixel_threshold = args.pixel_threshold;
  if (!std::isnan(args.max_percent_over)) t.max_percent_over = args.max_percent_over;
  if (!std::isnan(args.min_ssim)) t.min_ssim = args.min_ssim;
  if (!std::isnan(args.min_psnr_db)) t.min_psnr_db = args.min_psnr_db;
  return t;
}

std::string number(double v, int precision = 3, bool trim = true) {
  if (std::isinf(v)) return "inf";
  std::ostringstream s;
  s.precision(precision);
  s << std::fixed << v;
  std::string text = s.str();
  // 2.000 -> 2, 0.250 -> 0.25: the unit is an 8-bit step, mostly whole.
  if (trim && text.find('.') != std::string::npos) {
    text.erase(text.find_last_not_of('0') + 1);
    if (text.back() == '.') text.pop_back();
  }
  return text;
}

std::string limitText(const ToleranceCheck& c) {
  const std::string unit = c.metric == "max_abs"        ? "/255"
                           : c.metric == "percent_over" ? "%"
                           : c.metric == "psnr_db"      ? " dB"
                                                        : "";
  return std::string(c.at_most ? "<= " : ">= ") + number(c.limit, 4) + unit;
}

const ToleranceCheck* findCheck(const std::vector<ToleranceCheck>& checks, const char* metric) {
  for (const ToleranceCheck& c : checks)
    if (c.metric == metric) return &c;
  return nullptr;
}

// One aligned line: label, value, and the limit with its verdict when checked.
void printLine(const std::string& label, const std::string& value, const ToleranceCheck* check) {
  if (check == nullptr) {
    std::printf("  %-22s %s\n", label.c_str(), value.c_str());
    return;
  }
  std::printf("  %-22s %-40s", label.c_str(), value.c_str());
  if (check->metric == "hash") {
    std::printf(" %-17s %s", "must be equal", check->pass ? "ok" : "FAIL");
  } else {
    std::printf(" limit %-11s %s", limitText(*check).c_str(), check->pass ? "ok" : "FAIL");
  }
  std::printf("\n");
}

void printHuman(const CompareArgs& args, const ImageComparison& c, const CompareTolerance& t,
                const std::vector<ToleranceCheck>& checks, bool pass,
                const render::PngFormat& fa, const render::PngFormat& fb,
                const render::AlignedComparison* aligned) {
  const std::string where = aligned ? " in the canvas overlap" : "";
  if (c.identical) {
    std::printf("%s and %s: identical pixels%s (%dx%d, fnv1a64 %s); tolerance %s: pass\n",
                args.a.c_str(), args.b.c_str(), where.c_str(), c.width, c.height,
                hex64(c.hash_a).c_str(), t.name.c_str());
    return;
  }
  std::printf("%s and %s: %dx%d%s, pixels differ; tolerance %s: %s\n", args.a.c_str(),
              args.b.c_str(), c.width, c.height, where.c_str(), t.name.c_str(),
              pass ? "pass" : "FAIL");
  printLine("files", formatName(fa) + " vs " + formatName(fb), nullptr);
  std::int64_t pixels = std::int64_t(c.width) * c.height;
  if (aligned != nullptr) {
    printLine("overlap (canvas mm)", "from (" + number(aligned->overlap_x0_mm) + ", " +
                                         number(aligned->overlap_y0_mm) + "); b at (" +
                                         std::to_string(aligned->offset_x_px) + ", " +
                                         std::to_string(aligned->offset_y_px) + ") px from a",
              nullptr);
    printLine("ink outside overlap", std::to_string(aligned->ink_outside_a) + " px of a, " +
                                         std::to_string(aligned->ink_outside_b) + " px of b",
              nullptr);
    pixels = aligned->pixels;
  }
  // Aligned, equal hashes of the overlap still fail "exact" when ink lies outside it.
  const std::int64_t outside = aligned ? aligned->ink_outside_a + aligned->ink_outside_b : 0;
  printLine(aligned ? "pixel hash of overlap" : "pixel hash",
            hex64(c.hash_a) + " vs " + hex64(c.hash_b) +
                (outside ? ", ink outside" : ""),
            findCheck(checks, "hash"));
  const double largest = std::max({c.max_abs[0], c.max_abs[1], c.max_abs[2], c.max_abs[3]});
  printLine("max abs difference", number(largest) + "/255 (R " + number(c.max_abs[0]) + ", G " +
                                      number(c.max_abs[1]) + ", B " + number(c.max_abs[2]) +
                                      ", A " + number(c.max_abs[3]) + ")",
            findCheck(checks, "max_abs"));
  printLine("pixels over " + number(c.pixel_threshold) + "/255",
            std::to_string(c.pixels_over) + " of " + std::to_string(pixels) + " (" +
                number(c.percent_over, 4) + "%)",
            findCheck(checks, "percent_over"));
  printLine("pixels differing", std::to_string(c.pixels_differing), nullptr);
  printLine("RMSE", number(c.rmse, 4) + "/255", nullptr);
  printLine("PSNR", number(c.psnr_db, 2) + " dB", findCheck(checks, "psnr_db"));
  printLine("SSIM (luma)", number(c.ssim, 6, false), findCheck(checks, "ssim"));
}

nlohmann::json toleranceJson(const CompareTolerance& t) {
  nlohmann::json j{{"name", t.name}, {"require_identical", t.require_identical},
                   {"pixel_threshold", t.pixel_threshold}};
  j["max_abs"] = t.max_abs ? nlohmann::json(*t.max_abs) : nlohmann::json();
  j["max_percent_over"] = t.max_percent_over ? nlohmann::json(*t.max_percent_over) : nlohmann::json();
  j["min_ssim"] = t.min_ssim ? nlohmann::json(*t.min_ssim) : nlohmann::json();
  j["min_psnr_db"] = t.min_psnr_db ? nlohmann::json(*t.min_psnr_db) : nlohmann::json();
  return j;
}

nlohmann::json imageJson(const std::string& path, const render::Image16& image,
                         const render::PngFormat& f) {
  return {{"path", path},
          {"width", image.width},
          {"height", image.height},
          {"bit_depth", f.bit_depth},
          {"channels", f.channels}};
}

// Where `image` lies on the canvas, from its bristle:canvas text; 65 naming the
// file when the text is missing, malformed, or not of this image's size.
render::CanvasPlacement placementOf(const std::string& path, const render::PngText& text,
                                    const render::Image16& image) {
  const std::string name = path == "-" ? std::string(kStdinName) : path;
  for (const auto& [key, value] : text) {
    if (key != render::kCanvasTextKey) continue;
    render::CanvasPlacement p;
    if (!render::parseCanvasPlacement(value, &p))
      throw Error(ExitCode::kDataError,
                  name + ": " + render::kCanvasTextKey + " \"" + value +
                      "\": not \"x0_mm=X y0_mm=Y px_per_mm=S width_px=W height_px=H\"");
    if (p.width_px != image.width || p.height_px != image.height)
      throw Error(ExitCode::kDataError,
                  name + ": " + render::kCanvasTextKey + ": says " + std::to_string(p.width_px) +
                      "x" + std::to_string(p.height_px) + " px, but the image is " +
                      std::to_string(image.width) + "x" + std::to_string(image.height));
    return p;
  }
  throw Error(ExitCode::kDataError,
              name + ": no " + render::kCanvasTextKey +
                  " text chunk, which --align canvas needs (bristle render writes it for a "
                  "stroke or a scene; a preview or a sheet has none)");
}

std::string mmRange(const render::CanvasPlacement& p) {
  return "x " + number(p.x0_mm) + ".." + number(p.x0_mm + p.width_px / p.px_per_mm) + " mm, y " +
         number(p.y0_mm) + ".." + number(p.y0_mm + p.height_px / p.px_per_mm) + " mm";
}

// --align canvas: checks that a and b share a scale and a pixel grid (65
// otherwise), compares them over their overlap, and records the alignment in
// the --json object.
render::AlignedComparison compareOnCanvas(const CompareArgs& args, const render::Image16& a,
                                          const render::CanvasPlacement& pa,
                                          const render::Image16& b,
                                          const render::CanvasPlacement& pb,
                                          double pixel_threshold, nlohmann::json* j) {
  const std::string both = args.a + " and " + args.b + ": --align canvas: ";
  int dx = 0, dy = 0;
  if (std::fabs(pa.px_per_mm - pb.px_per_mm) > 1e-6 * std::max(pa.px_per_mm, pb.px_per_mm))
    throw Error(ExitCode::kDataError,
                both + "the scales differ (" + number(pa.px_per_mm, 6) + " and " +
                    number(pb.px_per_mm, 6) +
                    " px/mm); render both at one --px-per-mm (no resampling is done)");
  if (!render::canvasOffsetPx(pa, pb, &dx, &dy))
    throw Error(ExitCode::kDataError,
                both + "the canvases' pixel grids do not coincide (b's corner is not a whole "
                       "number of pixels from a's)");
  render::AlignedComparison aligned = render::compareAligned(a, pa, b, pb, pixel_threshold);
  (*j)["align"] = {{"mode", "canvas"},
                   {"a_canvas_mm", mmRange(pa)},
                   {"b_canvas_mm", mmRange(pb)},
                   {"px_per_mm", pa.px_per_mm},
                   {"b_offset_px", {dx, dy}},
                   {"overlap_x0_mm", aligned.overlap_x0_mm},
                   {"overlap_y0_mm", aligned.overlap_y0_mm},
                   {"overlap_width_px", aligned.overlap_width_px},
                   {"overlap_height_px", aligned.overlap_height_px},
                   {"ink_outside_a", aligned.ink_outside_a},
                   {"ink_outside_b", aligned.ink_outside_b}};
  return aligned;
}

// The measures, the checks and the verdict, for --json. `pixels` is the
// image's count, or aligned, the overlap's plus the ink outside it
// (percent_over's whole).
void addResultJson(const ImageComparison& c, std::int64_t pixels,
                   const std::vector<ToleranceCheck>& checks, bool pass, const std::string& diff,
                   nlohmann::json* out) {
  nlohmann::json& j = *out;
  j["hash_a"] = hex64(c.hash_a);
  j["hash_b"] = hex64(c.hash_b);
  j["identical"] = c.identical;
  j["max_abs"] = {{"r", c.max_abs[0]}, {"g", c.max_abs[1]}, {"b", c.max_abs[2]},
                  {"a", c.max_abs[3]}};
  j["pixel_threshold"] = c.pixel_threshold;
  j["pixels"] = pixels;
  j["pixels_differing"] = c.pixels_differing;
  j["pixels_over"] = c.pixels_over;
  j["percent_over"] = c.percent_over;
  j["rmse"] = c.rmse;
  // JSON has no infinity: identical images have no PSNR (null).
  j["psnr_db"] = std::isinf(c.psnr_db) ? nlohmann::json() : nlohmann::json(c.psnr_db);
  j["ssim"] = c.ssim;
  j["ssim_window"] = c.ssim_window;
  nlohmann::json list = nlohmann::json::array();
  for (const ToleranceCheck& k : checks) {
    list.push_back({{"metric", k.metric}, {"value", k.value}, {"limit", k.limit},
                    {"must_be", k.at_most ? "<=" : ">="}, {"pass", k.pass}});
  }
  j["checks"] = list;
  j["diff"] = diff.empty() ? nlohmann::json() : nlohmann::json(diff);
  j["verdict"] = pass ? "pass" : "fail";
}

}  // namespace

int runCompare(const CompareArgs& args) {
  checkPngOutputName("compare", "--diff", args.diff, false);
  const CompareTolerance tolerance = toleranceOf(args);
  checkCliFiles({{"--diff", args.diff}}, {{"a", args.a}, {"b", args.b}}, {}, {"a", "b"});
  render::PngFormat fa, fb;
  render::PngText ta, tb;
  const render::Image16 a = render::readPngRgba16(args.a, &fa, &ta);
  const render::Image16 b = render::readPngRgba16(args.b, &fb, &tb);
  const auto fail = static_cast<int>(ExitCode::kCheckFailed);

  nlohmann::json j{{"a", imageJson(args.a, a, fa)},
                   {"b", imageJson(args.b, b, fb)},
                   {"tolerance", toleranceJson(tolerance)}};
  // Images that cannot be compared pixel by pixel fail the check (exit 1), with
  // the reason on stderr and, under --json, in the object.
  auto incomparable = [&](const std::string& why) {
    if (args.json) {
      j["verdict"] = "fail";
      j["reason"] = why;
      std::cout << j.dump(2) << "\n";
    }
    printError(why);
    return fail;
  };
  render::CanvasPlacement pa, pb;
  render::AlignedComparison aligned;
  if (args.align == "canvas") {
    pa = placementOf(args.a, ta, a);
    pb = placementOf(args.b, tb, b);
    aligned = compareOnCanvas(args, a, pa, b, pb, tolerance.pixel_threshold, &j);
    if (aligned.overlap_width_px == 0) {
      return incomparable("canvases do not overlap: " + args.a + " covers " + mmRange(pa) +
                          ", " + args.b + " covers " + mmRange(pb));
    }
  } else if (a.width != b.width || a.height != b.height) {
    return incomparable("images differ in size: " + args.a + " is " + std::to_string(a.width) +
                        "x" + std::to_string(a.height) + ", " + args.b + " is " +
                        std::to_string(b.width) + "x" + std::to_string(b.height));
  }

  const bool align = args.align == "canvas";
  const ImageComparison c =
      align ? aligned.c : render::compareImages(a, b, tolerance.pixel_threshold);
  const std::vector<ToleranceCheck> checks = render::checkTolerance(c, tolerance);
  const bool pass = render::allPass(checks);
  if (!args.diff.empty()) {
    render::writePng(args.diff,
                     align ? render::alignedDifferenceImage(a, pa, b, pb, args.diff_gain)
                           : render::differenceImage(a, b, args.diff_gain),
                     {{"Software", "bristle compare"},
                      {"bristle:compare", args.a + " vs " + args.b}});
  }

  if (args.json) {
    addResultJson(c, align ? aligned.pixels : std::int64_t(c.width) * c.height, checks, pass,
                  args.diff, &j);
    std::cout << j.dump(2) << "\n";
  } else {
    printHuman(args, c, tolerance, checks, pass, fa, fb, align ? &aligned : nullptr);
    if (!args.diff.empty()) std::printf("  %-22s %s\n", "difference image", args.diff.c_str());
  }
  std::fflush(stdout);
  return pass ? 0 : fail;
}

Subcommand registerCompare(CLI::App& app) {
  auto cmp = std::make_shared<CompareArgs>();
  CLI::App* compare = app.add_subcommand(
      "compare", "Compare two PNGs: hash, differences, PSNR, SSIM against a tolerance");
  compare->footer(
      "Examples:\n"
      "  bristle compare golden/round-s-curve.png new.png --tolerance strict --diff d.png\n"
      "  bristle compare a.png b.png --json --max-abs 4 --min-ssim 0.995\n"
      "  bristle compare golden/round-s-curve.png new.png --align canvas --tolerance strict\n"
      "Differences are in 8-bit steps (1/255 of full scale) whatever the bit depth.\n"
      "Presets: exact (equal pixels; the default), strict (max abs <= 2, <= 0.1% of pixels\n"
      "over 1), loose (SSIM >= 0.99, <= 1% of pixels over 8). Exit 0 within tolerance, 1 not\n"
      "(also when the sizes differ).\n"
      "--align canvas compares two renders (strokes or scenes) where their canvases overlap,\n"
      "by the bristle:canvas text each PNG carries, so renders on canvases of different\n"
      "extent compare; ink outside the overlap counts as differing pixels. Both must have\n"
      "one px/mm; a PNG without the text is refused (65). See docs/golden-tests.md.");
  compare->add_option("a", cmp->a, "First PNG (the reference); - reads stdin")->required();
  compare->add_option("b", cmp->b, "Second PNG; - reads stdin")->required();
  compare->add_option("--diff", cmp->diff,
                      "Write the amplified difference image (PNG only: .jpg ... are refused)");
  compare->add_option("--align", cmp->align,
                      "canvas: compare two renders where their canvases overlap, by the "
                      "bristle:canvas text each PNG carries")
      ->check(CLI::IsMember({"canvas"}));
  compare->add_option("--diff-gain", cmp->diff_gain, "Amplification of --diff")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 65535.0));
  compare->add_flag("--json", cmp->json, "One JSON object on stdout: metrics, tolerance, verdict");
  compare->add_option("--tolerance", cmp->tolerance, "Preset: exact, strict or loose")
      ->check(CLI::IsMember({"exact", "strict", "loose"}));
  compare->add_option("--max-abs", cmp->max_abs, "Largest channel difference allowed (8-bit steps)")
      ->check(CLI::Range(0.0, 255.0));
  compare->add_option("--pixel-threshold", cmp->pixel_threshold,
                      "A pixel differs when a channel differs by more than this (8-bit steps)")
      ->check(CLI::Range(0.0, 255.0));
  compare->add_option("--max-percent-over", cmp->max_percent_over,
                      "Largest % of pixels over --pixel-threshold allowed")
      ->check(CLI::Range(0.0, 100.0));
  compare->add_option("--min-ssim", cmp->min_ssim, "Smallest SSIM allowed")
      ->check(CLI::Range(-1.0, 1.0));
  compare->add_option("--min-psnr", cmp->min_psnr_db, "Smallest PSNR allowed (dB)")
      ->check(CLI::Range(0.0, 1000.0));
  return {compare, [cmp] { return runCompare(*cmp); }};
}

}  // namespace bristle::cli
