#include "scenes/scene_files.hpp"

#include <system_error>

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

}  // namespace tumble
