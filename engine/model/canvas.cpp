#include "engine/model/canvas.h"

#include <algorithm>
#include <cmath>

namespace bristle {

bool parseHexColour(const std::string& text, Rgb* out) {
  if (text.size() != 7 || text[0] != '#') return false;
  int v[3];
  for (int i = 0; i < 3; ++i) {
    v[i] = 0;
    for (int k = 0; k < 2; ++k) {
      const char c = text[1 + 2 * i + k];
      int d;
      if (c >= '0' && c <= '9') d = c - '0';
      else if (c >= 'a' && c <= 'f') d = c - 'a' + 10;
      else if (c >= 'A' && c <= 'F') d = c - 'A' + 10;
      else return false;
      v[i] = v[i] * 16 + d;
    }
  }
  *out = Rgb{v[0] / 255.0, v[1] / 255.0, v[2] / 255.0};
  return true;
}

}  // namespace bristle
