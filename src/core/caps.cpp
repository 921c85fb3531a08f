#include "parallaxes/core/caps.h"

namespace px {

Caps Caps::full(int es_major) {
    Caps c;
    c.es_major = es_major;
    c.es_minor = 0;
    c.version = "OpenGL ES " + std::to_string(es_major) + ".0 (assumed)";
    c.extensions = {"GL_EXT_frag_depth", "GL_OES_standard_derivatives", "GL_OES_texture_npot",
                    "GL_OES_element_index_uint", "GL_KHR_debug"};
    return c;
}

}  // namespace px
