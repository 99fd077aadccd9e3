// Numbers in output files are written as the shortest decimal that reads back to the same
// double (std::to_chars), so outputs round-trip exactly and are byte-identical across runs.
#pragma once

#include <charconv>
#include <cstdio>
#include <ostream>
#include <string>

#include "collision/math.hpp"

namespace tumble::app {

inline void write_number(std::ostream& out, Real x) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  out.write(buffer, result.ptr - buffer);
}

inline std::string format_number(Real x) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
}

// A fixed number of digits after the point, for the tables benchmarks print.
inline std::string fixed_digits(double v, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, v);
  return buffer;
}

}  // namespace tumble::app
