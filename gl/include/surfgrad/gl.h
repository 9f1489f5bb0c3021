// Umbrella header of the gl module (surfgrad_gl, gl/).
// A headless OpenGL context (EGL surfaceless), program compilation with
// messages mapped back to shader files, and the harnesses that run shared
// shader functions on the GPU. Links shaders and base.
//
// Includes every public header of the module:
//   surfgrad/gl/context.h  HeadlessContext, Program, the compute and feedback harnesses
#pragma once

#include "surfgrad/gl/context.h"
