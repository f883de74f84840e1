#pragma once
// GL helpers shared by the renderers of render/: error checks and shader
// programs. Internal to render/ (it includes the GL headers; engine never does).

#include <GL/gl.h>
#include <GL/glext.h>

namespace bristle::render {

// Throws std::runtime_error "<who>: GL error 0x.... after <what>" if GL reports one.
void checkGl(const char* who, const char* what);

// Compiles and links a vertex + fragment shader pair, with a geometry shader
// between them when geometry_source is given; throws std::runtime_error with
// the driver's log, prefixed by `who`, when any of them fails.
GLuint linkProgram(const char* who, const char* vertex_source, const char* fragment_source,
                   const char* geometry_source = nullptr);

}  // namespace bristle::render
