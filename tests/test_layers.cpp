// The folders' one-way dependencies (issue 24, docs/architecture.md): every `#include
// "folder/..."` under src/ names the file's own folder or one listed before it in the layer
// line of docs/architecture.md; folders of one layer (written `a | b`) do not include each
// other. The line is read from the document, so the picture and the check cannot drift apart.
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace {

namespace fs = std::filesystem;

const fs::path kSource = TEARFLOW_SOURCE_DIR;

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" `");
  const size_t b = s.find_last_not_of(" `");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

/// folder -> layer index, from the line "core -> mesh -> geometry | fem -> ..." of the document.
std::map<std::string, int> layers_from(const fs::path& doc) {
  std::ifstream in(doc);
  std::string line;
  while (std::getline(in, line)) {
    if (trim(line).rfind("core ->", 0) != 0)
      continue;
    std::map<std::string, int> layer;
    std::stringstream arrows(trim(line));
    int index = 0;
    for (std::string part; std::getline(arrows, part, '>'); ++index) {
      if (!part.empty() && part.back() == '-')
        part.pop_back();
      std::stringstream peers(part);
      for (std::string name; std::getline(peers, name, '|');)
        layer[trim(name)] = index;
    }
    return layer;
  }
  return {};
}

struct Include {
  fs::path file;
  int line;
  std::string from, to;
};

std::vector<Include> includes_between_folders() {
  // "folder/..." or <folder/...>: src/ is on the include path, so both reach it.
  const std::regex include(R"(^\s*#\s*include\s*["<]([A-Za-z0-9_]+)/)");
  std::vector<Include> out;
  for (const auto& entry : fs::recursive_directory_iterator(kSource / "src")) {
    if (!entry.is_regular_file())
      continue;
    // The folder is the first part below src/, also for files in nested folders; a file
    // directly in src/ belongs to none and is reported.
    const fs::path relative = entry.path().lexically_relative(kSource / "src");
    const std::string folder =
        std::distance(relative.begin(), relative.end()) > 1 ? relative.begin()->string() : "";
    std::ifstream in(entry.path());
    std::string text;
    std::smatch m;
    for (int n = 1; std::getline(in, text); ++n)
      if (std::regex_search(text, m, include) && m[1] != folder)
        out.push_back({entry.path().lexically_relative(kSource), n, folder, m[1]});
  }
  return out;
}

TEST(Layers, EveryFolderOfSrcHasItsLayer) {
  const auto layer = layers_from(kSource / "docs" / "architecture.md");
  ASSERT_FALSE(layer.empty()) << "docs/architecture.md has no line 'core -> ...'";
  for (const auto& entry : fs::directory_iterator(kSource / "src")) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_directory())
      ADD_FAILURE() << name << " lies directly in src/, outside every folder";
    else
      EXPECT_TRUE(layer.count(name))
          << "src/" << name << " is not in docs/architecture.md's layer line";
  }
}

/// "file:line: from includes to, ..." for every include against the order.
std::vector<std::string> violations(const std::map<std::string, int>& layer,
                                    const std::vector<Include>& includes) {
  std::vector<std::string> out;
  for (const Include& i : includes) {
    if (!layer.count(i.from) || !layer.count(i.to))
      continue; // EveryFolderOfSrcHasItsLayer reports it
    if (layer.at(i.to) < layer.at(i.from))
      continue;
    out.push_back(i.file.string() + ":" + std::to_string(i.line) + ": " + i.from + " includes " +
                  i.to +
                  (layer.at(i.to) == layer.at(i.from) ? ", a folder of its own layer"
                                                      : ", a folder above it"));
  }
  return out;
}

TEST(Layers, NoFolderIncludesOneAboveItOrBesideIt) {
  const auto layer = layers_from(kSource / "docs" / "architecture.md");
  ASSERT_FALSE(layer.empty());
  const auto found = includes_between_folders();
  ASSERT_GT(found.size(), 100u) << "the scan found too few includes to be reading src/";
  for (const std::string& v : violations(layer, found))
    ADD_FAILURE() << v;
}

// The check itself: includes that break the order are reported, those that keep it are not.
TEST(Layers, ABackwardIncludeIsReported) {
  const auto layer = layers_from(kSource / "docs" / "architecture.md");
  const std::vector<Include> includes = {{"src/physics/a.cpp", 3, "physics", "io"},
                                         {"src/geometry/b.cpp", 5, "geometry", "fem"},
                                         {"src/io/c.cpp", 7, "io", "physics"},
                                         {"src/mesh/d.cpp", 9, "mesh", "core"}};
  const auto v = violations(layer, includes);
  ASSERT_EQ(v.size(), 2u);
  EXPECT_EQ(v[0], "src/physics/a.cpp:3: physics includes io, a folder above it");
  EXPECT_EQ(v[1], "src/geometry/b.cpp:5: geometry includes fem, a folder of its own layer");
}

} // namespace
