// JSON written by the commands: names come from file names and scenes and need not be valid
// UTF-8, which JSON requires; invalid bytes are written as U+FFFD instead of failing the write
// (nlohmann::json throws on them by default, after the other outputs were already written).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace tumble::app {

inline std::string json_text(const nlohmann::json& j, int indent = -1) {
  return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace tumble::app
