// The YAML scene loader on whole documents (aliases, anchors, nesting and all): a document is
// loaded and checked, or refused with a SceneError. Any other exception, a crash, a sanitizer
// report, a hang or an allocation beyond libFuzzer's limit is a finding.
#include <cstdint>
#include <string_view>

#include "tumble/load_scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    tumble::load_scene_text(text, "fuzz.yaml");
  } catch (const tumble::SceneError&) {
  }
  return 0;
}
