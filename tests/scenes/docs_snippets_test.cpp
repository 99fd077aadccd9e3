// Every YAML block of README.md and docs/*.md loads as what it shows: a scene, a fragment of one
// (such as the randomize block, loaded inside a minimal scene), a query file or a sweep file, in a
// folder laid out like scenes/ (its meshes and stack10.yaml beside it), so that no example names
// a file or field that does not exist.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "scenes/query_file.hpp"
#include "scenes/scene_loader.hpp"
#include "scenes/sweep_file.hpp"

namespace tumble {
namespace {

namespace fs = std::filesystem;

struct Snippet {
  std::string file;
  int line = 0;  // of the opening fence
  std::string text;
};

std::vector<Snippet> yaml_snippets() {
  const fs::path root(TUMBLE_SOURCE_DIR);
  std::vector<fs::path> files{root / "README.md"};
  for (const auto& entry : fs::directory_iterator(root / "docs"))
    if (entry.path().extension() == ".md")
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  std::vector<Snippet> out;
  for (const fs::path& path : files) {
    std::ifstream in(path);
    std::string line;
    Snippet* open = nullptr;
    for (int number = 1; std::getline(in, line); ++number) {
      if (open == nullptr && line.rfind("```yaml", 0) == 0) {
        out.push_back({path.filename().string(), number, ""});
        open = &out.back();
      } else if (open != nullptr && line.rfind("```", 0) == 0) {
        open = nullptr;
      } else if (open != nullptr) {
        open->text += line + "\n";
      }
    }
  }
  return out;
}

// Whether a line of `text` starts with `key:` (a key of the document's top level).
bool has_top_level_key(const std::string& text, const std::string& key) {
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind(key + ":", 0) == 0)
      return true;
  return false;
}

// A folder like scenes/: the meshes and the scene the sweep example names.
struct SceneFolder {
  fs::path dir;
  SceneFolder() {
    dir = fs::temp_directory_path() / ("tumble_docs_snippets_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path scenes = fs::path(TUMBLE_SOURCE_DIR) / "scenes";
    fs::copy(scenes / "meshes", dir / "meshes", fs::copy_options::recursive);
    fs::copy_file(scenes / "stack10.yaml", dir / "stack10.yaml");
  }
  ~SceneFolder() { fs::remove_all(dir); }
  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path path = dir / name;
    std::ofstream(path) << text;
    return path;
  }
};

TEST(DocsSnippets, EveryYamlBlockLoadsAsWhatItShows) {
  const std::vector<Snippet> snippets = yaml_snippets();
  ASSERT_GE(snippets.size(), 4u);  // the scene, randomize, query and sweep examples at least
  const SceneFolder folder;
  for (const Snippet& s : snippets) {
    const std::string where = s.file + ":" + std::to_string(s.line);
    try {
      if (has_top_level_key(s.text, "queries")) {
        EXPECT_FALSE(load_query_file(folder.write("queries.yaml", s.text)).empty()) << where;
      } else if (has_top_level_key(s.text, "vary")) {
        EXPECT_FALSE(load_sweep_file(folder.write("sweep.yaml", s.text)).axes.empty()) << where;
      } else if (has_top_level_key(s.text, "bodies")) {
        EXPECT_FALSE(load_scene_file(folder.write("scene.yaml", s.text)).bodies.empty()) << where;
      } else {
        // A fragment of a scene: inside a minimal one.
        const std::string scene =
            "world: {dt: 0.01, duration: 0.1}\n"
            "bodies: [{name: ball, shape: {type: sphere, radius: 0.1}, mass: 1}]\n" +
            s.text;
        EXPECT_FALSE(load_scene_file(folder.write("fragment.yaml", scene)).bodies.empty()) << where;
      }
    } catch (const std::exception& e) {
      ADD_FAILURE() << where << ": " << e.what();
    }
  }
}

}  // namespace
}  // namespace tumble
