// tumble's version, as the installed package reports it.
#pragma once

#define TUMBLE_VERSION_MAJOR 0
#define TUMBLE_VERSION_MINOR 1
#define TUMBLE_VERSION_PATCH 0

namespace tumble {

inline constexpr const char* kVersion = "0.1.0";

// The version the installed library was built as (equal to kVersion unless the headers and the
// library come from different installs).
const char* library_version();

}  // namespace tumble
