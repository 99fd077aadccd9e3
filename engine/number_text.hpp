// Numbers and vectors in error messages: the shortest text that reads back as the same double, and
// nan/inf spelled as YAML and Python spell them.
#pragma once

#include <charconv>
#include <cmath>
#include <string>

#include "tumble/math.hpp"

namespace tumble {

inline std::string number_text(Real v) {
  if (std::isnan(v))
    return "nan";
  if (std::isinf(v))
    return v > 0 ? "inf" : "-inf";
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, result.ptr);
}

// Built with append: GCC 12 warns falsely (-Wrestrict) about "(" + std::string when inlined.
inline std::string vector_text(const Vec3& v) {
  std::string text("(");
  text.append(number_text(v.x())).append(", ").append(number_text(v.y())).append(", ");
  text.append(number_text(v.z())).append(")");
  return text;
}

}  // namespace tumble
