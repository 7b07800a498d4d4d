// The OpenGL headers, with core entry points declared (libglvnd's libOpenGL exports them).
// Include this, never <GL/gl.h> directly, so every file sees the same prototypes.
#pragma once

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/gl.h>
#include <GL/glext.h>
