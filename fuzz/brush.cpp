// Fuzz target: the brush reader (bristle-brush/1 JSON), both as render reads a
// brush (the first problem throws) and as validate does (every problem listed).

#include "engine/formats/brush_reader.h"
#include "engine/model/brush.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = bristle::fuzz::text(data, size);
  try {
    const bristle::Brush brush = bristle::parseBrush(text, "fuzz.json");
    (void)brush.reachMm();
  } catch (const bristle::Error& e) {
    bristle::fuzz::checkRefusal(e);
  }
  try {
    // The problems may quote the file's bytes: validate prints them through
    // printError, which shows control characters as \u escapes (\u000a).
    std::vector<std::string> problems;
    (void)bristle::parseBrush(text, "fuzz.json", &problems);
  } catch (const bristle::Error& e) {
    bristle::fuzz::checkRefusal(e);
  }
  return 0;
}
