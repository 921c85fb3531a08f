// render/renderer.h texture_files(): in a file of its own, so that only a
// host that asks for files links the readers, the codecs and the upload of
// texture containers.
#include "parallaxes/render/renderer.h"

namespace px {

const TextureFileSupport* texture_files() {
    static const TextureFileSupport support{texture_file_readers(), upload_texture_data};
    return &support;
}

}  // namespace px
