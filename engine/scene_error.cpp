// SceneError's message (include/tumble/error.hpp).
#include <string>
#include <utility>

#include "engine/printable_text.hpp"
#include "tumble/error.hpp"

namespace tumble {

namespace {

std::string format_message(const std::string& file, int line, int column, const std::string& field,
                           const std::string& reason) {
  std::string m = printable_name(file);
  if (line > 0) {
    m.append(":").append(std::to_string(line)).append(":").append(std::to_string(column));
  }
  m.append(": ");
  if (!field.empty()) {
    m.append("field '").append(field).append("': ");
  }
  m.append(reason);
  return m;
}

}  // namespace

SceneError::SceneError(std::string file_, int line_, int column_, std::string field_,
                       std::string reason_)
    : Error(format_message(file_, line_, column_, field_, reason_)),
      file(std::move(file_)),
      line(line_),
      column(column_),
      field(std::move(field_)),
      reason(std::move(reason_)) {}

}  // namespace tumble
