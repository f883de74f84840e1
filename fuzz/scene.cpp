// Fuzz target: the scene reader (bristle-scene/1 JSON), the scene file alone:
// the brushes and trajectories it names are not opened.

#include "engine/formats/scene.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = bristle::fuzz::text(data, size);
  (void)bristle::looksLikeScene(text);
  try {
    (void)bristle::parseScene(text, "s.json", "/nonexistent");
  } catch (const bristle::Error& e) {
    bristle::fuzz::checkRefusal(e);
  }
  return 0;
}
