#include "renders/osmesa_library.hpp"

#include <dlfcn.h>

#include <array>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

namespace tumble::render {
namespace {

// The library's run-time name first (what Debian's libosmesa6 installs), then the development
// link a source build of Mesa leaves.
constexpr std::array<const char*, 2> kOsMesaLibraryNames = {"libOSMesa.so.8", "libOSMesa.so"};

// Either the loaded functions or why they could not be loaded; computed once.
struct OsMesaLoadResult {
  OsMesaLibrary functions;
  std::string problem;
};

OsMesaLoadResult load_osmesa() {
  OsMesaLoadResult result;
  void* handle = nullptr;
  std::string reasons;
  // TUMBLE_OSMESA_LIBRARY names another build of Mesa (a path, or a name the loader searches).
  std::vector<const char*> names(kOsMesaLibraryNames.begin(), kOsMesaLibraryNames.end());
  if (const char* chosen = std::getenv("TUMBLE_OSMESA_LIBRARY"); chosen != nullptr && *chosen)
    names = {chosen};
  for (const char* name : names) {
    // RTLD_LOCAL: Mesa's symbols stay out of the global namespace, so they cannot shadow
    // anything a later library defines.
    handle = dlopen(name, RTLD_NOW | RTLD_LOCAL);
    if (handle != nullptr)
      break;
    const char* reason = dlerror();
    reasons += std::string(reasons.empty() ? "" : "; ") + (reason != nullptr ? reason : name);
  }
  if (handle == nullptr) {
    result.problem =
        "rendering needs Mesa's off-screen OpenGL library libOSMesa.so.8 (Debian "
        "package libosmesa6; TUMBLE_OSMESA_LIBRARY names another), which could not "
        "be loaded: " +
        reasons;
    return result;
  }
  // Never closed: the renderer's contexts and Mesa's own exit-time records live in it.
  OsMesaLibrary& f = result.functions;
#define TUMBLE_OSMESA_LOAD(name)                                     \
  f.name = reinterpret_cast<decltype(f.name)>(dlsym(handle, #name)); \
  if (f.name == nullptr) {                                           \
    result.problem = "libOSMesa has no function " #name              \
                     ": the renderer needs OpenGL 1.1 and "          \
                     "OSMesa 11.2 or later";                         \
    return result;                                                   \
  }
  TUMBLE_OSMESA_FUNCTIONS(TUMBLE_OSMESA_LOAD)
#undef TUMBLE_OSMESA_LOAD
  return result;
}

}  // namespace

const OsMesaLibrary& osmesa_library() {
  static const OsMesaLoadResult loaded = load_osmesa();
  if (!loaded.problem.empty())
    throw std::runtime_error(loaded.problem);
  return loaded.functions;
}

}  // namespace tumble::render
