// MyPaint stroke-player event files (libmypaint's tests/events/*.dat): one
// event a line, `t x y pressure`, separated by blanks; t in seconds from the
// start, x and y in screen pixels (y down), pressure in [0, 1], 0 when the pen
// is in the air. No tilt: the pen is upright (docs/input.md, "MyPaint events").

#include <string>

#include "engine/base/error.h"
#include "input/recording.h"
#include "input/sample_checks.h"
#include "input/text_fields.h"

namespace bristle::input {

using namespace detail;

Recording readMyPaintEvents(const std::string& text, const std::string& path,
                            std::size_t max_samples) {
  checkSampleCount(countDataLines(text), max_samples, path, "event lines");
  static constexpr const char* kNames[] = {"t", "x", "y", "pressure"};
  Recording rec = newRecording(path, Format::kMyPaint, "screen pixels, assumed 96 per inch");
  Lines lines(text);
  std::string_view t;
  int no = 0;
  while (nextDataLine(lines, &t, &no)) {
    const std::vector<std::string_view> f = splitBlanks(t);
    if (f.size() != 4)
      throw dataError(path, place(no),
                      "has " + std::to_string(f.size()) +
                          " fields; a MyPaint event line is 't x y pressure' (4 numbers)");
    double v[4];
    for (int c = 0; c < 4; ++c) v[c] = parseNumber(f[c], path, no, c + 1, kNames[c]);
    PenSample s;
    s.line = no;
    s.t_s = checkTime(v[0], f[0], rec, path, no, 1, "t");
    s.x = checkCoordinate(v[1], f[1], path, no, 2, "x");
    s.y = checkCoordinate(v[2], f[2], path, no, 3, "y");
    s.pressure = checkPressure(v[3], f[3], path, no, 4, "pressure");
    s.down = s.pressure > 0;
    rec.samples.push_back(s);
  }
  return rec;
}

}  // namespace bristle::input
