#include "gl/bindings.h"

namespace subsplat::gl {

const std::string& glslBindingDefines() {
  static const std::string defines = [] {
    std::string text;
#define SUBSPLAT_DEFINE(name, value, ...) text += "#define " #name " " + std::to_string(value) + "\n";
    SUBSPLAT_TEXTURE_UNITS(SUBSPLAT_DEFINE)
    SUBSPLAT_IMAGE_UNITS(SUBSPLAT_DEFINE)
    SUBSPLAT_STORAGE_BINDINGS(SUBSPLAT_DEFINE)
    SUBSPLAT_SHARED_ENUMS(SUBSPLAT_DEFINE)
#undef SUBSPLAT_DEFINE
    return text;
  }();
  return defines;
}

}  // namespace subsplat::gl
