// Text quoted in messages (engine/printable_text.hpp).
#include "engine/printable_text.hpp"

namespace tumble {

namespace {

void append_printable(std::string& out, unsigned char c) {
  if (c < 0x20 || c == 0x7f) {
    constexpr std::string_view hex = "0123456789abcdef";
    out += "\\x";
    out += hex[c >> 4];
    out += hex[c & 15];
  } else {
    out += static_cast<char>(c);
  }
}

}  // namespace

std::string printable(std::string_view s) {
  constexpr std::size_t kMax = 60;
  std::string out;
  for (std::size_t i = 0; i < s.size() && i < kMax; ++i)
    append_printable(out, static_cast<unsigned char>(s[i]));
  if (s.size() > kMax) {
    out += "...";
  }
  return out;
}

std::string printable_name(std::string_view name) {
  std::string out;
  for (const char c : name)
    append_printable(out, static_cast<unsigned char>(c));
  return out;
}

}  // namespace tumble
