// The one include for OpenGL ES in the library. Declares ES 3.0 entry points;
// code calls ES 3.0-only functions only when Caps::es_major >= 3.
#pragma once

#include <GLES3/gl3.h>
#include <GLES2/gl2ext.h>
