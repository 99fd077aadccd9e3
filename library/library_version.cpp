// The version libtumble.so was built as, to compare with the headers a program compiled against.
#include "tumble/version.hpp"

namespace tumble {

const char* library_version() {
  return kVersion;
}

}  // namespace tumble
