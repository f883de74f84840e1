// Fuzz target: the stroke-sheet reader (bristle-sheet/1 JSON), the sheet file
// alone: the brushes and trajectories it lists are not opened.

#include "engine/formats/sheet.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = bristle::fuzz::text(data, size);
  (void)bristle::looksLikeSheet(text);
  try {
    (void)bristle::parseSheet(text, "sh.json", "/nonexistent");
  } catch (const bristle::Error& e) {
    bristle::fuzz::checkRefusal(e);
  }
  return 0;
}
