#pragma once
// An unknown GALLIUM_DRIVER segfaults inside OSMesa, and the tests expect
// llvmpipe: clear whatever the environment set before any context exists
// (static initialisation runs before main). Tests REQUIRE it was cleared.

#include <cstdlib>

inline const bool kGalliumDriverCleared = [] { return ::unsetenv("GALLIUM_DRIVER") == 0; }();
