// Text from a file or a command line quoted in a message: one line, short, and nothing a
// terminal would act on.
#pragma once

#include <string>
#include <string_view>

namespace tumble {

// `s` with control bytes written as \xNN and cut after 60 bytes (marked "...").
std::string printable(std::string_view s);
// A file's name as a message shows it: whole, control bytes (a NUL, which would end a message
// read as a C string, a newline, a terminal escape) written as \xNN.
std::string printable_name(std::string_view name);

}  // namespace tumble
