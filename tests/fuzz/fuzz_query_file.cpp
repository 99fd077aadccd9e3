// The query file parser of `tumble query` (scenes/query_file.hpp): queries are read, or the file
// is refused with a SceneError.
#include <cstdint>
#include <string_view>

#include "scenes/query_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    tumble::load_query_string(text, "fuzz_queries.yaml");
  } catch (const tumble::SceneError&) {
  }
  return 0;
}
