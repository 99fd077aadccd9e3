// Text from a file or a command line quoted in a message: one line, short, and nothing a
// terminal would act on.
#pragma once

#include <string>
#include <string_view>

namespace tumble {

// `s` with control bytes written as \xNN and cut after 60 bytes (marked "...").
std::string printable(std::string_view s);

}  // namespace tumble
