// `bristle compare` end to end: verdicts and exit codes, the human and JSON
// outputs, the difference image, bad input (sizes, truncated, missing), and
// --align canvas (renders on canvases of different extent, by their
// bristle:canvas text).

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli_runner.h"
#include "render/image/png_io.h"

using namespace bristle;
using namespace bristle::testing;
using Catch::Matchers::Contains;

namespace {

// A w x h 8-bit RGB image with a gradient, so SSIM has structure to see.
render::Image8 gradient(int w, int h) {
  render::Image8 im{w, h, 3, {}};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (const int v : {(x * 255) / (w - 1), (y * 255) / (h - 1), 128})
        im.pixels.push_back(static_cast<std::uint8_t>(v));
  return im;
}

std::string q(const std::string& path) { return "'" + path + "'"; }

// Values that pass through JSON as decimal text: 1e-9 is far below any
// difference the checks look for and far above printing error (~1e-15).
constexpr double kJsonTol = 1e-9;

}  // namespace

TEST_CASE("compare: identical images exit 0 and say so", "[cli][compare]") {
  TempDir dir;
  const std::string a = dir.file("a.png"), b = dir.file("b.png");
  render::writePng(a, gradient(40, 30));
  render::writePng(b, gradient(40, 30), {{"Comment", "other text, same pixels"}});
  const RunResult r = runBristle("compare " + q(a) + " " + q(b));
  CHECK(r.code == 0);
  CHECK_THAT(r.out, Contains("identical pixels (40x30"));
  CHECK(r.err.empty());
}

TEST_CASE("compare: one pixel off by 10 -- exact fails, a custom limit passes", "[cli][compare]") {
  TempDir dir;
  const std::string a = dir.file("a.png"), b = dir.file("b.png"), d = dir.file("d.png");
  render::Image8 im = gradient(40, 30);
  render::writePng(a, im);
  im.pixels[3 * (10 * 40 + 20) + 2] += 10;  // B of pixel (20, 10)
  render::writePng(b, im);

  RunResult r = runBristle("compare " + q(a) + " " + q(b));
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Contains("tolerance exact: FAIL"));
  CHECK_THAT(r.out, Contains("must be equal"));

  r = runBristle("compare " + q(a) + " " + q(b) + " --tolerance strict");
  CHECK(r.code == 1);  // max abs 10 > 2
  CHECK_THAT(r.out, Contains("10/255 (R 0, G 0, B 10, A 0)"));
  CHECK_THAT(r.out, Contains("limit <= 2/255"));

  // Limits alone make a custom tolerance: max 10 <= 10 and 1 of 1200 px
  // (0.083%) over 9 steps <= 0.1% pass; a limit of 9.5 steps does not.
  r = runBristle("compare " + q(a) + " " + q(b) +
                 " --max-abs 10 --pixel-threshold 9 --max-percent-over 0.1");
  CHECK(r.code == 0);
  CHECK_THAT(r.out, Contains("tolerance custom: pass"));
  CHECK_THAT(r.out, Contains("pixels over 9/255"));
  r = runBristle("compare " + q(a) + " " + q(b) + " --max-abs 9.5");
  CHECK(r.code == 1);
  // A preset with a limit changed: loose, but no more than 5 steps anywhere.
  r = runBristle("compare " + q(a) + " " + q(b) + " --tolerance loose --max-abs 5");
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Contains("tolerance loose+custom: FAIL"));
}

TEST_CASE("compare: --json has every metric, the tolerance and the verdict", "[cli][compare]") {
  TempDir dir;
  const std::string a = dir.file("a.png"), b = dir.file("b.png"), d = dir.file("d.png");
  render::Image8 im = gradient(40, 30);
  render::writePng(a, im);
  im.pixels[3 * (10 * 40 + 20) + 2] += 10;
  render::writePng(b, im);
  const RunResult r =
      runBristle("compare " + q(a) + " " + q(b) + " --json --tolerance strict --diff " + q(d));
  CHECK(r.code == 1);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  CHECK(j["verdict"] == "fail");
  CHECK(j["identical"] == false);
  CHECK(j["tolerance"]["name"] == "strict");
  CHECK(j["tolerance"]["max_abs"] == 2.0);
  CHECK(j["max_abs"]["b"].get<double>() == Approx(10).margin(kJsonTol));
  CHECK(j["max_abs"]["r"].get<double>() == 0);
  CHECK(j["pixels"] == 1200);
  CHECK(j["pixels_over"] == 1);
  CHECK(j["percent_over"].get<double>() == Approx(100.0 / 1200).epsilon(kJsonTol));
  // RMSE by hand: one squared difference of 100 among 3 * 1200 samples.
  CHECK(j["rmse"].get<double>() == Approx(std::sqrt(100.0 / 3600)).epsilon(kJsonTol));
  CHECK(j["psnr_db"].get<double>() == Approx(20 * std::log10(255 / std::sqrt(100.0 / 3600))).epsilon(kJsonTol));
  CHECK(j["ssim"].get<double>() < 1);
  CHECK(j["a"]["bit_depth"] == 8);
  CHECK(j["a"]["channels"] == 3);
  REQUIRE(j["checks"].size() == 2);
  CHECK(j["checks"][0]["metric"] == "max_abs");
  CHECK(j["checks"][0]["pass"] == false);
  CHECK(j["checks"][1]["metric"] == "percent_over");
  CHECK(j["checks"][1]["pass"] == true);  // 0.083% <= 0.1%
  CHECK(j["diff"] == d);

  // The difference image: the image's size, red at the changed pixel only.
  const render::Image8 diff = render::readPngRgba8(d);
  REQUIRE(diff.width == 40);
  REQUIRE(diff.height == 30);
  const std::uint8_t* p = &diff.pixels[4 * (10 * 40 + 20)];
  CHECK(int(p[0]) > 64);
  CHECK(int(p[1]) == 0);
  CHECK(int(p[2]) == 0);
  const std::uint8_t* e = &diff.pixels[4 * (10 * 40 + 30)];  // 10 px away: grey
  CHECK(int(e[0]) == int(e[1]));
  CHECK(int(e[1]) == int(e[2]));

  // Identical images: PSNR is infinite, which JSON writes as null.
  const nlohmann::json same =
      nlohmann::json::parse(runBristle("compare " + q(a) + " " + q(a) + " --json").out);
  CHECK(same["verdict"] == "pass");
  CHECK(same["psnr_db"].is_null());
  CHECK(same["ssim"] == 1.0);
}

TEST_CASE("compare: 8-bit RGB against 16-bit RGBA of the same picture", "[cli][compare]") {
  TempDir dir;
  const render::Image8 im8 = gradient(20, 10);
  render::Image16 im16{20, 10, 4, {}};
  for (std::size_t i = 0; i < im8.pixels.size(); i += 3) {
    for (int c = 0; c < 3; ++c) im16.pixels.push_back(static_cast<std::uint16_t>(im8.pixels[i + c] * 257));
    im16.pixels.push_back(65535);
  }
  render::writePng(dir.file("a.png"), im8);
  render::writePng(dir.file("b.png"), im16);
  const RunResult r = runBristle("compare " + q(dir.file("a.png")) + " " + q(dir.file("b.png")));
  CHECK(r.code == 0);
  CHECK_THAT(r.out, Contains("identical pixels"));
}

TEST_CASE("compare: bad input", "[cli][compare][errors]") {
  TempDir dir;
  const std::string a = dir.file("a.png"), b = dir.file("b.png");
  render::writePng(a, gradient(40, 30));
  render::writePng(b, gradient(41, 30));

  RunResult r = runBristle("compare " + q(a) + " " + q(b));
  CHECK(r.code == 1);
  CHECK_THAT(r.err, Contains("differ in size"));
  CHECK_THAT(r.err, Contains("40x30"));
  CHECK_THAT(r.err, Contains("41x30"));
  r = runBristle("compare " + q(a) + " " + q(b) + " --json");
  CHECK(r.code == 1);
  CHECK(nlohmann::json::parse(r.out)["verdict"] == "fail");

  // Truncated: the first half of a valid file.
  const std::string whole = readAll(a);
  const std::string cut = dir.write("cut.png", whole.substr(0, whole.size() / 2));
  r = runBristle("compare " + q(a) + " " + q(cut));
  CHECK(r.code == 65);
  CHECK_THAT(r.err, Contains("cut.png"));
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);

  const std::string text = dir.write("text.png", "not a png\n");
  r = runBristle("compare " + q(text) + " " + q(a));
  CHECK(r.code == 65);
  CHECK_THAT(r.err, Contains("text.png: not a PNG"));

  r = runBristle("compare " + q(a) + " " + q(dir.file("missing.png")));
  CHECK(r.code == 66);
  CHECK_THAT(r.err, Contains("missing.png"));

  r = runBristle("compare " + q(a) + " " + q(a) + " --tolerance fuzzy");
  CHECK(r.code == 64);
  r = runBristle("compare " + q(a) + " " + q(a) + " --tolerance exact --max-abs 3");
  CHECK(r.code == 64);
  CHECK_THAT(r.err, Contains("exact takes no limits"));

  // The difference image cannot be created: 73, and no verdict is claimed.
  r = runBristle("compare " + q(a) + " " + q(a) + " --diff " + q(dir.file("no/such/dir.png")));
  CHECK(r.code == 73);
}

TEST_CASE("compare: a stroke rendered at 16 bits differs from its 8-bit render by rounding only",
          "[cli][compare]") {
  TempDir dir;
  const std::string stroke = "render --brush " + q(sourcePath("scenes/brushes/bright.json")) +
                             " --trajectory " + q(sourcePath("scenes/trajectories/press-lift.csv")) +
                             " --solver slsqp --offset-mm 0 0 -5.4 -q";
  REQUIRE(runBristle(stroke + " -o " + q(dir.file("8.png"))).code == 0);
  REQUIRE(runBristle(stroke + " --bits 16 -o " + q(dir.file("16.png"))).code == 0);
  const RunResult r =
      runBristle("compare " + q(dir.file("8.png")) + " " + q(dir.file("16.png")) +
                 " --json --tolerance strict");
  const nlohmann::json j = nlohmann::json::parse(r.out);
  CHECK(j["b"]["bit_depth"] == 16);
  // The 8-bit file is the 16-bit one rounded to the nearest 8-bit level, so no
  // sample is more than half a step away (plus the 1/257-step grid of 16 bits).
  constexpr double kHalfStep = 0.5 + 1.0 / 257;
  for (const char* c : {"r", "g", "b", "a"}) CHECK(j["max_abs"][c].get<double>() <= kHalfStep);
  CHECK(j["pixels_over"] == 0);  // none over 1 step
  CHECK(j["verdict"] == "pass");
  CHECK(r.code == 0);
}

// ---- --align canvas ---------------------------------------------------------

namespace {

// The renderer's placement text (cli canvasText's format).
std::string canvasText(double x0, double y0, double ppm, int w, int h) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "x0_mm=%.6f y0_mm=%.6f px_per_mm=%.6f width_px=%d height_px=%d",
                x0, y0, ppm, w, h);
  return buf;
}

// A w x h white 8-bit RGB image with black pixels at the (column, row) given.
render::Image8 paperWith(int w, int h, const std::vector<std::pair<int, int>>& ink) {
  render::Image8 im{w, h, 3, std::vector<std::uint8_t>(std::size_t(w) * h * 3, 255)};
  for (const auto& [x, y] : ink)
    for (int c = 0; c < 3; ++c) im.pixels[3 * (std::size_t(y) * w + x) + c] = 0;
  return im;
}

// A vertical round's dab that comes down, drifts 2 mm along x and lifts in
// 0.5 s; `excursion` adds a move through the air to x = 60 mm afterwards,
// which widens the canvas (sized to all the brush can reach) and paints
// nothing; `second_dab` brings the brush down there too.
std::string dabTrajectory(bool excursion, bool second_dab = false) {
  std::ostringstream s;
  s << "# bristle-trajectory/1\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n";
  for (int i = 0; i <= 25; ++i) {
    const double t = i * 0.02, u = t / 0.5;
    s << t << "," << 20 + 2 * u << ",20," << 22 - 5 * std::sin(M_PI * u) << ",1,0,0,0\n";
  }
  if (excursion) {
    s << "0.7,22,20,40,1,0,0,0\n0.9,60,20,40,1,0,0,0\n";
    if (second_dab) s << "1.1,60,20,17,1,0,0,0\n1.3,60,20,40,1,0,0,0\n";
  }
  return s.str();
}

}  // namespace

TEST_CASE("compare --align canvas: one stroke on two canvas extents is identical where they overlap",
          "[cli][compare][align]") {
  TempDir dir;
  const std::string render = "render -q --brush round --trajectory ";
  const std::string narrow = dir.file("narrow.png"), wide = dir.file("wide.png");
  REQUIRE(runBristle(render + q(dir.write("n.csv", dabTrajectory(false))) + " -o " + q(narrow))
              .code == 0);
  REQUIRE(runBristle(render + q(dir.write("w.csv", dabTrajectory(true))) + " -o " + q(wide))
              .code == 0);
  const render::Image8 n = render::readPngRgba8(narrow), w = render::readPngRgba8(wide);
  REQUIRE(w.width > n.width);  // the excursion widened the canvas

  // Pixel for pixel they cannot be compared; by the canvas they are the same stroke.
  RunResult r = runBristle("compare " + q(narrow) + " " + q(wide));
  CHECK(r.code == 1);
  CHECK_THAT(r.err, Contains("differ in size"));
  r = runBristle("compare " + q(narrow) + " " + q(wide) + " --align canvas");
  CHECK(r.code == 0);
  CHECK_THAT(r.out, Contains("identical pixels in the canvas overlap (" + std::to_string(n.width) +
                             "x" + std::to_string(n.height)));
  r = runBristle("compare " + q(wide) + " " + q(narrow) + " --align canvas --json");
  CHECK(r.code == 0);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  CHECK(j["identical"] == true);
  CHECK(j["align"]["overlap_width_px"] == n.width);
  CHECK(j["align"]["overlap_height_px"] == n.height);
  CHECK(j["align"]["ink_outside_a"] == 0);
  CHECK(j["align"]["ink_outside_b"] == 0);
  CHECK(j["pixels"] == std::int64_t(n.width) * n.height);

  // A genuinely different stroke: the same dab 1 mm further along y.
  const std::string moved = dir.file("moved.png");
  REQUIRE(runBristle(render + q(dir.file("w.csv")) + " --offset-mm 0 1 0 -o " + q(moved)).code == 0);
  r = runBristle("compare " + q(narrow) + " " + q(moved) + " --align canvas --json --diff " +
                 q(dir.file("d.png")));
  CHECK(r.code == 1);
  const nlohmann::json m = nlohmann::json::parse(r.out);
  CHECK(m["verdict"] == "fail");
  CHECK(m["align"]["b_offset_px"] == nlohmann::json{0, 8});  // 1 mm at 8 px/mm, y up
  CHECK(m["pixels_over"].get<int>() > 100);
  // The difference image spans both canvases.
  const render::Image8 d = render::readPngRgba8(dir.file("d.png"));
  CHECK(d.width == w.width);
  CHECK(d.height == n.height + 8);

  // The same stroke, with a second dab beyond the narrow canvas: equal in the
  // overlap, and the ink outside it counts as differing pixels.
  const std::string two = dir.file("two.png");
  REQUIRE(runBristle(render + q(dir.write("t.csv", dabTrajectory(true, true))) + " -o " + q(two))
              .code == 0);
  r = runBristle("compare " + q(narrow) + " " + q(two) + " --align canvas --json");
  CHECK(r.code == 1);
  const nlohmann::json t = nlohmann::json::parse(r.out);
  CHECK(t["align"]["ink_outside_a"] == 0);
  const std::int64_t outside = t["align"]["ink_outside_b"].get<std::int64_t>();
  CHECK(outside > 100);
  CHECK(t["max_abs"]["r"] == 0.0);  // the overlap alone is identical
  CHECK(t["pixels_over"] == outside);
  CHECK(t["pixels"] == std::int64_t(n.width) * n.height + outside);
  // A tolerance that allows that share of differing pixels passes.
  r = runBristle("compare " + q(narrow) + " " + q(two) + " --align canvas --max-percent-over 100");
  CHECK(r.code == 0);
  CHECK_THAT(r.out, Contains("ink outside overlap    0 px of a, " + std::to_string(outside) +
                             " px of b"));
}

TEST_CASE("compare --align canvas: pixels meet by canvas millimetres, y up", "[cli][compare][align]") {
  TempDir dir;
  // a: 40 x 30 px at 2 px/mm from (0, 0) mm, a mark at column 12, row 20.
  // b: 20 x 15 px from (5, 4) mm = 10 px right and 8 px up of a's corner, so
  // a's column 12 is b's column 2, and a's row 20 (9 px above a's bottom edge)
  // is b's row 15 - 1 - (9 - 8) = 13.
  const std::string a = dir.file("a.png"), b = dir.file("b.png"), c = dir.file("c.png");
  render::writePng(a, paperWith(40, 30, {{12, 20}}), {{"bristle:canvas", canvasText(0, 0, 2, 40, 30)}});
  render::writePng(b, paperWith(20, 15, {{2, 13}}), {{"bristle:canvas", canvasText(5, 4, 2, 20, 15)}});
  RunResult r = runBristle("compare " + q(a) + " " + q(b) + " --align canvas --json");
  CHECK(r.code == 0);
  nlohmann::json j = nlohmann::json::parse(r.out);
  CHECK(j["align"]["b_offset_px"] == nlohmann::json{10, 8});
  CHECK(j["align"]["overlap_x0_mm"] == 5.0);
  CHECK(j["align"]["overlap_y0_mm"] == 4.0);
  // The mark one row off (as if rows counted from the top): a difference
  // inside the overlap, and b's paper where a has its mark.
  render::writePng(c, paperWith(20, 15, {{2, 12}}), {{"bristle:canvas", canvasText(5, 4, 2, 20, 15)}});
  r = runBristle("compare " + q(a) + " " + q(c) + " --align canvas --json");
  CHECK(r.code == 1);
  j = nlohmann::json::parse(r.out);
  CHECK(j["pixels_over"] == 2);
  // A mark of a outside b's canvas: one pixel of ink outside the overlap.
  render::writePng(a, paperWith(40, 30, {{12, 20}, {1, 1}}),
                   {{"bristle:canvas", canvasText(0, 0, 2, 40, 30)}});
  r = runBristle("compare " + q(a) + " " + q(b) + " --align canvas --json");
  CHECK(r.code == 1);
  j = nlohmann::json::parse(r.out);
  CHECK(j["align"]["ink_outside_a"] == 1);
  CHECK(j["pixels_over"] == 1);
  CHECK(j["pixels"] == 20 * 15 + 1);
  // Canvases that do not meet: the images differ (1), as images of different sizes do.
  render::writePng(c, paperWith(20, 15, {}), {{"bristle:canvas", canvasText(50, 4, 2, 20, 15)}});
  r = runBristle("compare " + q(a) + " " + q(c) + " --align canvas");
  CHECK(r.code == 1);
  CHECK_THAT(r.err, Contains("canvases do not overlap: " + a + " covers x 0..20 mm, y 0..15 mm"));
}

TEST_CASE("compare --align canvas: other scales, no canvas text or a broken one are refused",
          "[cli][compare][align][errors]") {
  TempDir dir;
  const std::string a = dir.file("a.png"), b = dir.file("b.png");
  render::writePng(a, paperWith(40, 30, {}), {{"bristle:canvas", canvasText(0, 0, 8, 40, 30)}});
  const auto refused = [&](const std::string& b_text, const std::string& message) {
    INFO(b_text);
    if (b_text.empty())
      render::writePng(b, paperWith(40, 30, {}));
    else
      render::writePng(b, paperWith(40, 30, {}), {{"bristle:canvas", b_text}});
    const RunResult r = runBristle("compare " + q(a) + " " + q(b) + " --align canvas");
    CHECK(r.code == 65);
    CHECK(r.out.empty());
    CHECK_THAT(r.err, Contains(message));
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  };
  refused(canvasText(0, 0, 6, 40, 30),
          a + " and " + b + ": --align canvas: the scales differ (8 and 6 px/mm)");
  refused("", b + ": no bristle:canvas text chunk, which --align canvas needs");
  refused("x0_mm=0 y0_mm=0", b + ": bristle:canvas \"x0_mm=0 y0_mm=0\": not \"x0_mm=X");
  refused(canvasText(0, 0, 8, 41, 30), b + ": bristle:canvas: says 41x30 px, but the image is 40x30");
  refused(canvasText(0.0625, 0, 8, 40, 30), "pixel grids do not coincide");
  // Without --align the text is not read: same pixels, same verdict as ever.
  render::writePng(b, paperWith(40, 30, {}));
  CHECK(runBristle("compare " + q(a) + " " + q(b)).code == 0);
  CHECK(runBristle("compare " + q(a) + " " + q(b) + " --align pixels").code == 64);
}
