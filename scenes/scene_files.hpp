// Where the files a scene names are looked up, and which of them it may name
// (SceneLoadOptions::allow_outside_files in tumble/load_scene.hpp).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace tumble {

// `name` as the document `source` (a file path, or a name such as "<text>" for a document with
// no file, whose folder is the current one) refers to it: relative names from that folder.
std::filesystem::path file_beside(const std::string& source, const std::string& name);

// The folder `file` would have to lie in (the document's own, symbolic links resolved) when it
// lies outside it; nothing when it lies in that folder or below.
std::optional<std::filesystem::path> outside_folder_of(const std::string& source,
                                                       const std::filesystem::path& file);

// Whether `path` is a regular file of at most scene_limits::kMaxFileBytes; otherwise `why` says
// what it is (as below). For files another library opens itself (OpenVDB's).
bool is_regular_file_within_limits(const std::filesystem::path& path, std::string& why);

// The whole of `path` when it is a regular file that can be read; otherwise nothing, and `why`
// says what is wrong ("No such file or directory", "Is a directory", "not a regular file", ...).
// Only regular files are read: a FIFO would block the read for ever and a device such as
// /dev/zero never ends. A file larger than scene_limits::kMaxFileBytes (1 GiB) is refused before
// it is read. Every file a scene, query or mesh names is read through here.
std::optional<std::string> regular_file_text(const std::filesystem::path& path, std::string& why);

}  // namespace tumble
