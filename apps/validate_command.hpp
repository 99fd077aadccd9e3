// `tumble validate`: load and check a scene without running it.
#pragma once

#include <filesystem>

namespace tumble::app {

// Returns 0 when the scene is valid (a one-line description on stdout), 1 otherwise.
int validate_command(const std::filesystem::path& scene);

}  // namespace tumble::app
