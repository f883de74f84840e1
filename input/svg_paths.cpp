// SVG paths as pen motion (docs/input.md, "SVG"): pugixml reads the document,
// lib2geom parses path data, applies the transforms and measures arc length.
// Each <path> subpath, <polyline>, <polygon>, <line>, <circle>, <ellipse> and
// <rect> is one stroke, drawn
// in document order at a constant speed, sampled every sample_mm along its
// arc length, its pressure following a profile over the fraction of its
// length (the default ramps in, holds and ramps out; data-bristle-pressure on
// the element or an ancestor overrides it). Between strokes the pen is up.

#include <2geom/affine.h>
#include <2geom/path.h>
#include <2geom/pathvector.h>
#include <2geom/sbasis-geometric.h>
#include <2geom/path-sink.h>
#include <2geom/svg-path-parser.h>
#include <2geom/transforms.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <pugixml.hpp>
#include <set>
#include <string>
#include <vector>

#include "engine/base/error.h"
#include "input/recording.h"
#include "input/svg_geometry.h"
#include "input/text_fields.h"

namespace bristle::input {

namespace {

using detail::trim;

// The byte offsets of the text's line starts, for "line L" of an element.
class LineIndex {
 public:
  explicit LineIndex(const std::string& text) {
    starts_.push_back(0);
    for (std::size_t i = 0; i < text.size(); ++i)
      if (text[i] == '\n') starts_.push_back(i + 1);
  }
  int lineOf(std::ptrdiff_t offset) const {
    if (offset < 0) return 0;
    const auto it = std::upper_bound(starts_.begin(), starts_.end(),
                                     static_cast<std::size_t>(offset));
    return static_cast<int>(it - starts_.begin());
  }

 private:
  std::vector<std::size_t> starts_;
};

// An element's local name: "svg:path" and "path" are both "path".
std::string localName(const pugi::xml_node& n) {
  const char* name = n.name();
  const char* colon = std::strchr(name, ':');
  return colon ? std::string(colon + 1) : std::string(name);
}

// Whether the element is in another XML namespace than SVG's by its prefix
// (inkscape:, sodipodi:, ...): such elements are editors' notes, skipped.
bool foreignPrefix(const pugi::xml_node& n) {
  const char* colon = std::strchr(n.name(), ':');
  return colon && std::strncmp(n.name(), "svg:", 4) != 0;
}

// Containers whose children are drawn; elements that draw nothing.
const std::set<std::string> kGroups = {"svg", "g", "a", "switch"};
const std::set<std::string> kNonDrawing = {
    "defs",   "title",          "desc",          "metadata", "style",  "script",
    "symbol", "clipPath",       "mask",          "marker",   "pattern", "linearGradient",
    "radialGradient", "filter", "namedview"};
const std::set<std::string> kStrokes = {"path",   "polyline", "polygon", "line",
                                         "circle", "ellipse",  "rect"};

struct Frame {
  pugi::xml_node node;
  Geom::Affine ctm;  // user units of this node's children to the root's
  // data-bristle-pressure in force: the attribute's text, which lives as long
  // as the document ("" : the default). A pointer, so that a long profile on
  // the root is neither copied into every frame nor parsed for every element.
  const char* pressure = "";
};

struct PendingStroke {
  Geom::Path path;  // in root user units
  std::shared_ptr<const std::vector<ProfilePoint>> profile;  // shared by an element's subpaths
  int line = 0;
  double length_units = 0;
};

// "<path id="leaf"> (line 12)": how messages name an element.
std::string describe(const pugi::xml_node& n, int line) {
  std::string s = "<" + std::string(n.name());
  if (const pugi::xml_attribute id = n.attribute("id")) s += " id=\"" + std::string(id.value()) + "\"";
  return s + "> (line " + std::to_string(line) + ")";
}

// The scale the root element implies: its width (or height) against its
// viewBox, in mm per user unit; a CSS pixel when it gives none.
double documentMmPerUnit(const pugi::xml_node& root, const std::string& path, int line,
                         std::string* note) {
  constexpr double kPx = 25.4 / 96;
  const char* vb = root.attribute("viewBox").value();
  const std::vector<double> box = parseNumberList(vb, path, describe(root, line) + ": viewBox");
  if (box.empty()) {
    *note = "SVG user units = CSS px, 96 per inch (the root has no viewBox)";
    return kPx;
  }
  if (box.size() != 4 || !(box[2] > 0) || !(box[3] > 0))
    throw dataError(path, describe(root, line),
                    "viewBox = \"" + std::string(vb) +
                        "\": must be four numbers 'min-x min-y width height', width and height > 0");
  for (const char* attr : {"width", "height"}) {
    const std::string value(trim(root.attribute(attr).value()));
    if (value.empty()) continue;
    const double mm = lengthMm(value);
    if (mm > 0) {
      *note = "SVG " + std::string(attr) + "=\"" + value + "\" over viewBox " + attr +
              " " + formatNumber(box[attr[0] == 'w' ? 2 : 3]) + " user units";
      return mm / box[attr[0] == 'w' ? 2 : 3];
    }
  }
  *note = "SVG user units = CSS px, 96 per inch (no width or height in absolute units)";
  return kPx;
}

// One number attribute of `n`; `fallback` when it is absent.
double numberAttribute(const pugi::xml_node& n, const char* attr, double fallback,
                       const std::string& path, const std::string& where) {
  const std::vector<double> one =
      parseNumberList(n.attribute(attr).value(), path, where + ": " + attr);
  if (one.size() > 1) throw dataError(path, where, std::string(attr) + ": must be one number");
  return one.empty() ? fallback : one[0];
}

// Path data of a basic shape, as SVG defines its outline (SVG 2, "Basic
// shapes"): where the outline starts and which way it runs set where the
// brush lands and how it travels. Empty when the shape draws nothing (a zero
// radius, width or height); a negative one is an error.
std::string shapePathData(const pugi::xml_node& n, const std::string& name,
                          const std::string& path, const std::string& where) {
  auto num = [&](const char* attr, double fallback) {
    return numberAttribute(n, attr, fallback, path, where);
  };
  auto nonNegative = [&](const char* attr, double v) {
    if (v < 0) throw dataError(path, where, std::string(attr) + ": must be >= 0");
    return v;
  };
  char d[1024];  // 20 numbers of at most 24 characters, and the commands
  if (name == "circle" || name == "ellipse") {
    const double cx = num("cx", 0), cy = num("cy", 0);
    double rx = 0, ry = 0;
    if (name == "circle") {
      rx = ry = nonNegative("r", num("r", 0));
    } else {
      const pugi::xml_attribute ax = n.attribute("rx"), ay = n.attribute("ry");
      rx = nonNegative("rx", num("rx", 0));
      ry = nonNegative("ry", num("ry", 0));
      if (ax && !ay) ry = rx;  // one given: the other is the same ("auto")
      if (ay && !ax) rx = ry;
    }
    if (!(rx > 0 && ry > 0)) return "";
    // From (cx + rx, cy), the positive angle first: two half arcs.
    std::snprintf(d, sizeof d,
                  "M %.17g %.17g A %.17g %.17g 0 0 1 %.17g %.17g A %.17g %.17g 0 0 1 %.17g %.17g Z",
                  cx + rx, cy, rx, ry, cx - rx, cy, rx, ry, cx + rx, cy);
    return d;
  }
  // rect
  const double x = num("x", 0), y = num("y", 0);
  const double w = nonNegative("width", num("width", 0));
  const double h = nonNegative("height", num("height", 0));
  if (!(w > 0 && h > 0)) return "";
  const pugi::xml_attribute ax = n.attribute("rx"), ay = n.attribute("ry");
  double rx = nonNegative("rx", num("rx", 0)), ry = nonNegative("ry", num("ry", 0));
  if (ax && !ay) ry = rx;
  if (ay && !ax) rx = ry;
  rx = std::min(rx, w / 2);
  ry = std::min(ry, h / 2);
  if (!(rx > 0 && ry > 0)) {
    std::snprintf(d, sizeof d, "M %.17g %.17g H %.17g V %.17g H %.17g Z", x, y, x + w, y + h, x);
    return d;
  }
  std::snprintf(d, sizeof d,
                "M %.17g %.17g H %.17g A %.17g %.17g 0 0 1 %.17g %.17g V %.17g "
                "A %.17g %.17g 0 0 1 %.17g %.17g H %.17g A %.17g %.17g 0 0 1 %.17g %.17g "
                "V %.17g A %.17g %.17g 0 0 1 %.17g %.17g Z",
                x + rx, y, x + w - rx, rx, ry, x + w, y + ry, y + h - ry, rx, ry, x + w - rx, y + h,
                x + rx, rx, ry, x, y + h - ry, y + ry, rx, ry, x + rx, y);
  return d;
}

// The path segments an SVG has used of its limit (kMaxSvgSegments).
struct SegmentBudget {
  std::size_t used = 0, limit = 0;
  // Takes `count` more, or refuses the file naming the element and the limit.
  void take(std::size_t count, const std::string& path, const std::string& where) {
    used += count;
    if (used > limit)
      throw dataError(path, where,
                      "the SVG's paths hold more than " + std::to_string(limit) +
                          " segments, the limit for an SVG (its paths are held in memory whole)");
  }
};

// lib2geom's path builder, each move, line, curve and arc counted against the
// budget before the builder allocates it.
class CountingBuilder : public Geom::PathBuilder {
 public:
  CountingBuilder(SegmentBudget* budget, const std::string& path, const std::string& where)
      : budget_(budget), path_(path), where_(where + ": d") {}
  void moveTo(const Geom::Point& p) override { take(), PathBuilder::moveTo(p); }
  void lineTo(const Geom::Point& p) override { take(), PathBuilder::lineTo(p); }
  void quadTo(const Geom::Point& c, const Geom::Point& p) override {
    take(), PathBuilder::quadTo(c, p);
  }
  void curveTo(const Geom::Point& c0, const Geom::Point& c1, const Geom::Point& p) override {
    take(), PathBuilder::curveTo(c0, c1, p);
  }
  void arcTo(Geom::Coord rx, Geom::Coord ry, Geom::Coord angle, bool large_arc, bool sweep,
             const Geom::Point& p) override {
    take(), PathBuilder::arcTo(rx, ry, angle, large_arc, sweep, p);
  }

 private:
  void take() { budget_->take(1, path_, where_); }
  SegmentBudget* budget_;
  const std::string& path_;
  std::string where_;
};

// Path data as lib2geom parses it, counted against the budget.
Geom::PathVector parsePathData(const char* d, SegmentBudget* budget, const std::string& path,
                               const std::string& where) {
  CountingBuilder builder(budget, path, where);
  try {
    Geom::parse_svg_path(d, builder);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw dataError(path, where, "d: malformed path data (" + std::string(e.what()) + ")");
  }
  builder.flush();
  return builder.peek();
}

// The items of a number list, counted without storing them.
std::size_t countItems(const char* text) {
  std::size_t items = 0;
  bool in_item = false;
  for (const char* c = text; *c; ++c) {
    const bool sep = *c == ' ' || *c == '\t' || *c == '\n' || *c == '\r' || *c == ',';
    if (!sep && !in_item) ++items;
    in_item = !sep;
  }
  return items;
}

// The strokes of one drawing element, in root user units.
void addStrokes(const pugi::xml_node& n, const std::string& name, const Geom::Affine& ctm,
                const std::string& where, const std::string& path, SegmentBudget* budget,
                Geom::PathVector* out) {
  Geom::PathVector pv;
  if (name == "path") {
    pv = parsePathData(n.attribute("d").value(), budget, path, where);
  } else if (name == "line") {
    budget->take(2, path, where);
    Geom::Path p(Geom::Point(numberAttribute(n, "x1", 0, path, where),
                             numberAttribute(n, "y1", 0, path, where)));
    p.appendNew<Geom::LineSegment>(Geom::Point(numberAttribute(n, "x2", 0, path, where),
                                               numberAttribute(n, "y2", 0, path, where)));
    pv.push_back(p);
  } else if (name == "circle" || name == "ellipse" || name == "rect") {
    const std::string d = shapePathData(n, name, path, where);
    if (!d.empty()) pv = parsePathData(d.c_str(), budget, path, where);
  } else {  // polyline, polygon: each point a segment (the first the move)
    const char* points = n.attribute("points").value();
    budget->take((countItems(points) + 1) / 2, path, where + ": points");
    const std::vector<double> pts = parseNumberList(points, path, where + ": points");
    if (pts.size() % 2 != 0)
      throw dataError(path, where, "points: holds an odd count of numbers (" +
                                       std::to_string(pts.size()) + "): must be x,y pairs");
    if (pts.size() >= 4) {
      Geom::Path p(Geom::Point(pts[0], pts[1]));
      for (std::size_t i = 2; i + 1 < pts.size(); i += 2)
        p.appendNew<Geom::LineSegment>(Geom::Point(pts[i], pts[i + 1]));
      if (name == "polygon") p.close(true);
      pv.push_back(p);
    }
  }
  for (Geom::Path& p : pv) {
    p *= ctm;
    out->push_back(p);
  }
}

// display="none", or display:none in the style attribute (how Inkscape
// hides a layer): the element and everything in it are not drawn.
bool hidden(const pugi::xml_node& n) {
  if (std::strcmp(n.attribute("display").value(), "none") == 0) return true;
  const std::string style = n.attribute("style").value();
  std::size_t at = 0;
  while ((at = style.find("display", at)) != std::string::npos) {
    std::size_t i = at + 7;
    while (i < style.size() && (style[i] == ' ' || style[i] == '\t')) ++i;
    if (i < style.size() && style[i] == ':') {
      ++i;
      while (i < style.size() && (style[i] == ' ' || style[i] == '\t')) ++i;
      if (style.compare(i, 4, "none") == 0 &&
          (i + 4 == style.size() || style[i + 4] == ';' || style[i + 4] == ' ' ||
           style[i + 4] == '!'))
        return true;
    }
    at = i;
  }
  return false;
}

// What the walk over the document gathers: the strokes, and what it skipped.
struct SvgWalk {
  std::vector<PendingStroke> strokes;
  std::map<std::string, int> unsupported;  // element name -> count
  std::string first_unsupported;           // where the first of them is
  int empty_subpaths = 0;
};

// Samples a stroke of this length (user units) takes: along it at
// options.sample_mm, plus its ends and the hovers around it (sampleStrokes).
double strokeSamples(double length_units, double mm_per_unit, const SvgOptions& options) {
  return std::ceil(length_units * mm_per_unit / options.sample_mm) + 3;
}

// Walks the tree in document order with an explicit stack (no recursion, so
// no depth of nesting can overflow the stack), gathering the strokes in root
// user units. The samples they will take are counted as they are gathered,
// so a document of millions of tiny paths is refused before it is all held.
SvgWalk gatherStrokes(const pugi::xml_node& root, int root_line, const LineIndex& lines,
                      const std::string& path, const SvgOptions& options, double mm_per_unit,
                      std::size_t max_samples) {
  SvgWalk walk;
  double samples = 0;
  SegmentBudget budget{0, options.max_segments};
  std::vector<Frame> stack;
  for (pugi::xml_node c = root.last_child(); c; c = c.previous_sibling())
    stack.push_back({c, Geom::identity(), ""});
  const char* root_profile = root.attribute("data-bristle-pressure").value();
  for (Frame& f : stack) f.pressure = root_profile;
  // Each profile text parsed once (keyed by the attribute's text).
  std::map<const char*, std::shared_ptr<const std::vector<ProfilePoint>>> profiles;
  const Geom::Affine root_ctm = parseTransform(root.attribute("transform").value(), path,
                                               describe(root, root_line) + ": transform");
  for (Frame& f : stack) f.ctm = root_ctm;
  while (!stack.empty()) {
    const Frame f = stack.back();
    stack.pop_back();
    const pugi::xml_node n = f.node;
    if (n.type() != pugi::node_element || foreignPrefix(n)) continue;
    const std::string name = localName(n);
    if (kNonDrawing.count(name)) continue;
    const int line = lines.lineOf(n.offset_debug());
    const std::string where = describe(n, line);
    if (hidden(n)) continue;
    const Geom::Affine ctm =
        parseTransform(n.attribute("transform").value(), path, where + ": transform") * f.ctm;
    const pugi::xml_attribute own = n.attribute("data-bristle-pressure");
    const char* pressure = own ? own.value() : f.pressure;
    if (name == "switch") {
      // A viewer draws only the first child whose conditions hold; bristle
      // supports no extensions, and takes the other conditions as holding.
      for (pugi::xml_node c = n.first_child(); c; c = c.next_sibling())
        if (c.type() == pugi::node_element && *c.attribute("requiredExtensions").value() == '\0') {
          stack.push_back({c, ctm, pressure});
          break;
        }
      continue;
    }
    if (kGroups.count(name) && name != "svg") {
      for (pugi::xml_node c = n.last_child(); c; c = c.previous_sibling())
        stack.push_back({c, ctm, pressure});
      continue;
    }
    if (!kStrokes.count(name)) {
      if (walk.unsupported[name]++ == 0 && walk.first_unsupported.empty())
        walk.first_unsupported = where;
      continue;
    }
    std::shared_ptr<const std::vector<ProfilePoint>>& profile = profiles[pressure];
    if (!profile)
      profile = std::make_shared<const std::vector<ProfilePoint>>(parsePressureProfile(
          *pressure == '\0' ? options.pressure_profile : std::string(pressure), path,
          where + ": data-bristle-pressure"));
    Geom::PathVector pv;
    addStrokes(n, name, ctm, where, path, &budget, &pv);
    for (const Geom::Path& p : pv) {
      if (!pathWithinLimits(p))
        throw dataError(path, where,
                        "a point, control point or arc radius lies beyond +-1e9 user units (the "
                        "limit on positions) or is not finite");
      PendingStroke s;
      s.path = p;
      s.line = line;
      s.profile = profile;
      s.length_units = pathLength(p);
      if (!std::isfinite(s.length_units))
        throw dataError(path, where, "its length cannot be measured (lib2geom's integral fails)");
      if (s.length_units <= 0) {
        ++walk.empty_subpaths;
        continue;
      }
      samples += strokeSamples(s.length_units, mm_per_unit, options);
      if (samples > static_cast<double>(max_samples))
        detail::checkSampleCount(max_samples + 1, max_samples, path, "samples along its paths");
      walk.strokes.push_back(std::move(s));
    }
  }
  return walk;
}

// A document with nothing to draw is an error; what was skipped is a warning.
void reportSkipped(const SvgWalk& walk, const std::string& root_where, const std::string& path,
                   Recording* rec) {
  std::string skipped;
  for (const auto& [name, count] : walk.unsupported)
    skipped += (skipped.empty() ? "" : ", ") + std::to_string(count) + " <" + name + ">";
  if (walk.strokes.empty()) {
    if (!walk.first_unsupported.empty())
      throw dataError(path, walk.first_unsupported,
                      "no drawable path: bristle imports <path>, <polyline>, <polygon>, <line>, "
                      "<circle>, <ellipse> and <rect>, and this SVG holds only elements it does "
                      "not (" + skipped + ")");
    throw dataError(path, root_where,
                    "no drawable path: no <path>, <polyline>, <polygon>, <line>, <circle>, "
                    "<ellipse> or <rect> of any length");
  }
  if (!skipped.empty())
    rec->warnings.push_back(path + ": skipped " + skipped +
                            " (bristle imports <path>, <polyline>, <polygon>, <line>, <circle>, "
                            "<ellipse> and <rect>; "
                            "convert text and other elements to paths)");
  if (walk.empty_subpaths > 0)
    rec->warnings.push_back(path + ": skipped " + std::to_string(walk.empty_subpaths) +
                            " subpath(s) of zero length");
}

// Samples the strokes one after another at options.speed_mm_s, the pen lifted
// between them: a hover sample before and after each, options.lead_s away.
void sampleStrokes(const std::vector<PendingStroke>& strokes, const SvgOptions& options,
                   std::size_t max_samples, const std::string& path, Recording* rec) {
  // Sample counts first: a huge path is refused before anything is stored.
  const double mm = rec->mm_per_unit;
  std::size_t total = 0;
  for (const PendingStroke& s : strokes) {
    const double n = strokeSamples(s.length_units, mm, options);
    total += n > static_cast<double>(max_samples) ? max_samples + 1 : static_cast<std::size_t>(n);
    if (total > max_samples) break;
  }
  detail::checkSampleCount(total, max_samples, path, "samples along its paths");

  double t = 0;
  Geom::Point last_up;
  bool first = true;
  for (const PendingStroke& s : strokes) {
    const Geom::Point start = s.path.initialPoint();
    if (!first) t += std::max(Geom::distance(last_up, start) * mm / options.speed_mm_s, 0.05);
    first = false;
    auto add = [&](const Geom::Point& p, double time, double pressure, bool down) {
      PenSample ps;
      ps.t_s = time;
      ps.x = p.x();
      ps.y = p.y();
      ps.pressure = pressure;
      ps.down = down;
      ps.line = s.line;
      rec->samples.push_back(ps);
    };
    add(start, t, 0, false);
    t += options.lead_s;
    const std::vector<Geom::Point> pts = samplePath(s.path, s.length_units * mm / options.sample_mm);
    const double duration = s.length_units * mm / options.speed_mm_s;
    for (std::size_t k = 0; k < pts.size(); ++k) {
      const double u = pts.size() > 1 ? static_cast<double>(k) / (pts.size() - 1) : 0;
      add(pts[k], t + u * duration, profilePressure(*s.profile, u), true);
    }
    t += duration + options.lead_s;
    last_up = s.path.finalPoint();
    add(last_up, t, 0, false);
  }
}

}  // namespace

Recording readSvg(const std::string& text, const std::string& path, const SvgOptions& options,
                  std::size_t max_samples) {
  // pugixml holds the whole document; a file of millions of tags (each at
  // least a few samples if it draws) is refused before it is parsed.
  const std::size_t tags = static_cast<std::size_t>(std::count(text.begin(), text.end(), '<'));
  if (tags > kMaxSvgTags)
    throw dataError(path, "size",
                    "holds " + std::to_string(tags) + " tags, over the limit of " +
                        std::to_string(kMaxSvgTags) +
                        " for an SVG (its elements are read into memory whole)");
  const LineIndex lines(text);
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed = doc.load_buffer(text.data(), text.size());
  if (!parsed)
    throw dataError(path, "line " + std::to_string(lines.lineOf(parsed.offset)),
                    std::string("malformed XML (") + parsed.description() + ")");
  const pugi::xml_node root = doc.document_element();
  const int root_line = lines.lineOf(root.offset_debug());
  if (localName(root) != "svg")
    throw dataError(path, describe(root, root_line),
                    "the document element must be <svg> (an SVG file)");

  Recording rec;
  rec.path = path;
  rec.format = Format::kSvg;
  const double doc_scale = documentMmPerUnit(root, path, root_line, &rec.units_note);
  rec.mm_per_unit = options.mm_per_unit > 0 ? options.mm_per_unit : doc_scale;
  if (options.mm_per_unit > 0)
    rec.units_note = "SVG user units at " + formatNumber(1 / options.mm_per_unit) +
                     " per mm (given on the command line)";
  const SvgWalk walk =
      gatherStrokes(root, root_line, lines, path, options, rec.mm_per_unit, max_samples);
  reportSkipped(walk, describe(root, root_line), path, &rec);
  sampleStrokes(walk.strokes, options, max_samples, path, &rec);
  return rec;
}

}  // namespace bristle::input
