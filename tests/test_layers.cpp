// The folders' layers (docs/contributing.md, "The folders"): no include runs
// upward, the pipeline never knows about time, and schemes never include
// each other. Read from the sources, so a new include that breaks the map
// fails here rather than in a review.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>

namespace oovr {
namespace {

namespace fs = std::filesystem;

// What each folder of src/oovr may include besides itself (the map in
// docs/contributing.md).
const std::map<std::string, std::set<std::string>> kMayInclude = {
    {"core", {}},
    {"scene", {"core"}},
    {"pipeline", {"core", "scene"}},
    {"memory", {"core", "scene", "pipeline"}},
    {"timing", {"core", "memory"}},
    {"framework", {"core", "scene", "pipeline"}},
    {"schemes", {"core", "scene", "pipeline", "memory", "timing", "framework"}},
    {"run", {"core", "scene", "pipeline", "memory", "timing", "framework", "schemes"}},
    {"experiments", {"core", "scene", "pipeline", "memory", "timing", "framework", "schemes", "run"}},
    {"python", {"core", "scene", "pipeline", "memory", "timing", "framework", "schemes", "run", "experiments"}},
};

struct Include {
  std::string file, folder, path;  // the including file, its folder, the included "oovr/..." path
};

std::vector<Include> includes() {
  std::vector<Include> out;
  const fs::path root = fs::path(OOVR_SOURCE_DIR) / "src" / "oovr";
  const std::regex line(R"re(^\s*#\s*include\s*"oovr/([a-z_]+/[^"]+)")re");
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    const std::string ext = e.path().extension().string();
    if (!e.is_regular_file() || (ext != ".h" && ext != ".cpp")) continue;
    const std::string rel = fs::relative(e.path(), root).generic_string();
    std::ifstream in(e.path());
    std::string text;
    std::smatch m;
    while (std::getline(in, text))
      if (std::regex_search(text, m, line)) out.push_back({rel, rel.substr(0, rel.find('/')), m[1].str()});
  }
  return out;
}

TEST(Layers, NoIncludeRunsUpward) {
  const std::vector<Include> all = includes();
  ASSERT_GT(all.size(), 300u);  // the scan found the sources
  std::set<std::string> folders;
  for (const Include& i : all) {
    folders.insert(i.folder);
    const auto allowed = kMayInclude.find(i.folder);
    ASSERT_NE(allowed, kMayInclude.end()) << i.file << ": a folder the map does not know";
    const std::string target = i.path.substr(0, i.path.find('/'));
    if (target == i.folder) continue;
    EXPECT_TRUE(allowed->second.count(target))
        << i.file << " includes oovr/" << i.path << ": " << i.folder << " may not include " << target;
  }
  EXPECT_EQ(folders.size(), kMayInclude.size());
}

TEST(Layers, SchemesNeverIncludeEachOther) {
  size_t impl = 0;
  for (const Include& i : includes()) {
    if (i.file.rfind("schemes/impl/", 0) != 0) continue;
    ++impl;
    EXPECT_NE(i.path.rfind("schemes/impl/", 0), 0u) << i.file << " includes another scheme, oovr/" << i.path;
  }
  EXPECT_GT(impl, 10u);
}

}  // namespace
}  // namespace oovr
