#include "render/gl/gl_program.h"

#include <cstdio>
#include <stdexcept>
#include <string>

namespace bristle::render {
namespace {

GLuint compileShader(const char* who, GLenum type, const char* source) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    char log[1024] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    glDeleteShader(shader);
    throw std::runtime_error(std::string(who) + ": shader does not compile: " + log);
  }
  return shader;
}

}  // namespace

void checkGl(const char* who, const char* what) {
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR) {
    char message[200];
    std::snprintf(message, sizeof message, "%s: GL error 0x%04x after %s", who, error, what);
    throw std::runtime_error(message);
  }
}

GLuint linkProgram(const char* who, const char* vertex_source, const char* fragment_source,
                   const char* geometry_source) {
  const GLuint vs = compileShader(who, GL_VERTEX_SHADER, vertex_source);
  const GLuint fs = compileShader(who, GL_FRAGMENT_SHADER, fragment_source);
  const GLuint gs =
      geometry_source ? compileShader(who, GL_GEOMETRY_SHADER, geometry_source) : 0;
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  if (gs) glAttachShader(program, gs);
  glLinkProgram(program);
  glDeleteShader(vs);  // flagged; freed with the program
  glDeleteShader(fs);
  if (gs) glDeleteShader(gs);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    char log[1024] = {};
    glGetProgramInfoLog(program, sizeof log, nullptr, log);
    glDeleteProgram(program);
    throw std::runtime_error(std::string(who) + ": shaders do not link: " + log);
  }
  return program;
}

}  // namespace bristle::render
