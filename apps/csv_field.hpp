// One CSV field, quoted by RFC 4180 only when it holds a comma, quote or line break.
#pragma once

#include <ostream>
#include <string>

namespace tumble::app {

inline void write_csv_field(std::ostream& out, const std::string& field) {
  if (field.find_first_of(",\"\r\n") == std::string::npos) {
    out << field;
    return;
  }
  out << '"';
  for (const char c : field) {
    if (c == '"')
      out << '"';
    out << c;
  }
  out << '"';
}

}  // namespace tumble::app
