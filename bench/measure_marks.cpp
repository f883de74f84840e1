// Measures of a painted mark in a PNG (tests/support/mark_measure.h), for docs
// scripts: mean width and width CV over the middle 60% of the stroke, blots
// (components of at least 4 px) and the fill of the largest one's convex hull.
//
//   measure_marks PNG [--px-per-mm N] [--axis x|y] [--threshold T] [--json]
//
// The resolution comes from the PNG's bristle:canvas chunk unless --px-per-mm
// is given (8 when neither). Exit 0, 64 bad command line, 65/66 bad or missing PNG.

#include <cstdio>
#include <cstdlib>
#include <string>

#include "engine/base/error.h"
#include "tests/support/mark_measure.h"
#include "tests/support/mark_png.h"

namespace {

void usage(FILE* to) {
  std::fprintf(to,
               "usage: measure_marks PNG [--px-per-mm N] [--axis x|y] [--threshold T] [--json]\n"
               "  Ink = drop in luminance below the paper (the top-left pixel), or alpha.\n"
               "  --axis: the direction the stroke runs (width is measured across it).\n"
               "  --threshold: a pixel is inked above this ink level (default 0.1).\n");
}

std::string jsonEscape(const std::string& s) {
  std::string out;
  for (char ch : s) {
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (static_cast<unsigned char>(ch) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned char>(ch));
      out += buf;
    } else {
      out += ch;
    }
  }
  return out;
}

bool parseNumber(const std::string& text, double* out) {
  char* end = nullptr;
  *out = std::strtod(text.c_str(), &end);
  return end && *end == '\0' && !text.empty();
}

}  // namespace

int main(int argc, char** argv) {
  using namespace bristle;
  using namespace bristle::testsupport;
  std::string png;
  double ppm = 0, threshold = 0.1;
  Axis axis = Axis::kX;
  bool json = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "measure_marks: %s needs a value\n", a.c_str());
        std::exit(64);
      }
      return argv[++i];
    };
    if (a == "--px-per-mm") {
      if (!parseNumber(value(), &ppm) || !(ppm > 0)) {
        std::fprintf(stderr, "measure_marks: --px-per-mm must be a number > 0\n");
        return 64;
      }
    } else if (a == "--threshold") {
      if (!parseNumber(value(), &threshold) || !(threshold >= 0 && threshold < 1)) {
        std::fprintf(stderr, "measure_marks: --threshold must be a number in [0, 1)\n");
        return 64;
      }
    } else if (a == "--axis") {
      const std::string v = value();
      if (v == "x") {
        axis = Axis::kX;
      } else if (v == "y") {
        axis = Axis::kY;
      } else {
        std::fprintf(stderr, "measure_marks: --axis must be x or y\n");
        return 64;
      }
    } else if (a == "--json") {
      json = true;
    } else if (a == "-h" || a == "--help") {
      usage(stdout);
      return 0;
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "measure_marks: unknown option '%s'\n", a.c_str());
      usage(stderr);
      return 64;
    } else if (png.empty()) {
      png = a;
    } else {
      std::fprintf(stderr, "measure_marks: one PNG only\n");
      return 64;
    }
  }
  if (png.empty()) {
    usage(stderr);
    return 64;
  }
  try {
    const Coverage img = loadCoveragePng(png, ppm);
    const WidthProfile p = widthProfile(img, threshold, axis);
    const BlotStats b = blotStats(img, threshold);
    const double mean = meanWidthMm(p), cv = widthCv(p);
    const double length_mm = p.empty() ? 0 : (p.last - p.first + 1) / img.px_per_mm;
    if (json) {
      std::printf(
          "{\"png\": \"%s\", \"px_per_mm\": %.6g, \"axis\": \"%s\", \"threshold\": %.6g, "
          "\"length_mm\": %.4f, \"mean_width_mm\": %.4f, \"width_cv\": %.5f, "
          "\"components\": %d, \"specks\": %d, \"largest_area_mm2\": %.4f, "
          "\"largest_hull_area_mm2\": %.4f, \"fill\": %.5f}\n",
          jsonEscape(png).c_str(), img.px_per_mm, axis == Axis::kX ? "x" : "y", threshold,
          length_mm, mean,
          cv, b.components, b.specks, b.largest_area_mm2, b.largest_hull_area_mm2, b.fill);
    } else {
      std::printf("%s (%.4g px/mm, stroke along %s, ink > %.3g)\n", png.c_str(), img.px_per_mm,
                  axis == Axis::kX ? "x" : "y", threshold);
      std::printf("  length        %.3f mm\n", length_mm);
      std::printf("  mean width    %.3f mm (middle 60%%)\n", mean);
      std::printf("  width CV      %.4f\n", cv);
      std::printf("  components    %d (+%d specks < 4 px)\n", b.components, b.specks);
      std::printf("  largest blot  %.3f mm2, hull %.3f mm2, fill %.4f\n", b.largest_area_mm2,
                  b.largest_hull_area_mm2, b.fill);
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "measure_marks: %s\n", e.what());
    return static_cast<int>(e.code());
  }
  return 0;
}
