#include "scenes/scene_files.hpp"

#include <cerrno>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

#include "engine/scene_limits.hpp"

namespace tumble {
namespace {

// The absolute form with every existing part's symbolic links resolved and '.' and '..' gone,
// so that neither `../` nor a link inside the folder leads out of it unseen.
std::filesystem::path resolved(const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::path absolute = std::filesystem::absolute(path, ec);
  if (ec)
    absolute = path;
  std::filesystem::path canonical = std::filesystem::weakly_canonical(absolute, ec);
  return ec ? absolute.lexically_normal() : canonical;
}

std::filesystem::path folder_of(const std::string& source) {
  const std::filesystem::path parent = std::filesystem::path(source).parent_path();
  return parent.empty() ? std::filesystem::path(".") : parent;
}

}  // namespace

std::filesystem::path file_beside(const std::string& source, const std::string& name) {
  const std::filesystem::path path(name);
  return path.is_relative() ? folder_of(source) / path : path;
}

std::optional<std::filesystem::path> outside_folder_of(const std::string& source,
                                                       const std::filesystem::path& file) {
  const std::filesystem::path folder = resolved(folder_of(source));
  const std::filesystem::path target = resolved(file);
  const std::filesystem::path relative = target.lexically_relative(folder);
  if (!relative.empty() && *relative.begin() != ".." && relative.is_relative())
    return std::nullopt;
  return folder;
}

bool is_regular_file_within_limits(const std::filesystem::path& path, std::string& why) {
  // The system reads a name up to its first NUL byte: "scene.yaml\0.txt" would open scene.yaml.
  if (path.native().find('\0') != std::string::npos) {
    why = "the file name holds a NUL byte";
    return false;
  }
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (status.type() == std::filesystem::file_type::not_found) {
    why = std::make_error_code(std::errc::no_such_file_or_directory).message();
    return false;
  }
  if (ec) {
    why = ec.message();
    return false;
  }
  if (status.type() == std::filesystem::file_type::directory) {
    why = std::make_error_code(std::errc::is_a_directory).message();
    return false;
  }
  if (status.type() != std::filesystem::file_type::regular) {
    why = "not a regular file";
    return false;
  }
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (!ec && bytes > scene_limits::kMaxFileBytes) {
    why = "larger than the limit of 1 GiB for a file tumble reads (";
    why += std::to_string(bytes);
    why += " bytes)";
    return false;
  }
  return true;
}

std::optional<std::string> regular_file_text(const std::filesystem::path& path, std::string& why) {
  if (!is_regular_file_within_limits(path, why))
    return std::nullopt;
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    why = errno != 0 ? std::generic_category().message(errno) : "unreadable";
    return std::nullopt;
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) {
    why = "read error";
    return std::nullopt;
  }
  return std::move(text).str();
}

}  // namespace tumble
