// The version libtumble_render.so was built as.
#include "tumble/render.hpp"
#include "tumble/version.hpp"

namespace tumble {

const char* render_library_version() {
  return kVersion;
}

}  // namespace tumble
