#include "study/study_spec.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>

#include <fmt/format.h>

#include "core/digest.hpp"
#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "io/case_yaml.hpp"

namespace tearflow::study {

namespace {
/// A name that is one folder inside the study's output: '.' and '..' are not.
bool is_folder_name(const std::string& name) {
  return std::regex_match(name, std::regex("[A-Za-z0-9_.-]+")) && name != "." && name != "..";
}
} // namespace

namespace {

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// `tearflow geometry tbad` options from a mapping of them (key: the option without "--",
/// with '_' or '-'; value: a scalar or a list of numbers), checked against `known`.
void read_geometry(const io::YamlValue& map, const std::vector<std::string>& known,
                   std::map<std::string, std::string>& into) {
  for (const auto& [key, value] : map.entries()) {
    std::string option = key;
    std::replace(option.begin(), option.end(), '_', '-');
    if (option == "output" || option == "o")
      value.fail("the study chooses the geometry's output folder");
    if (std::find(known.begin(), known.end(), option) == known.end()) {
      const std::string near = nearest_name(option, known);
      value.fail(fmt::format("not an option of `tearflow geometry tbad`{} (docs/geometry.md)",
                             near.empty() ? "" : fmt::format("; did you mean '{}'?", near)));
    }
    if (value.is_list()) {
      std::string joined;
      for (double x : value.numbers())
        joined += fmt::format("{}{}", joined.empty() ? "" : " ", x);
      into[option] = joined;
    } else if (value.is_scalar()) {
      into[option] = value.text();
    } else {
      value.fail_expected("a number, a word or a list of numbers");
    }
  }
}

/// Targets: a file name (relative to the study file) or the targets mapping itself (`raw`),
/// merged over the study's `tuning` defaults (the variant's keys win).
YAML::Node read_targets(const io::YamlValue& value, const YAML::Node& raw,
                        const std::filesystem::path& dir, const YAML::Node& defaults) {
  YAML::Node targets = defaults.IsMap() ? YAML::Clone(defaults) : YAML::Node(YAML::NodeType::Map);
  YAML::Node own;
  if (value.is_scalar()) {
    const std::filesystem::path file = io::resolve_path(dir, value.text());
    if (!std::filesystem::exists(file))
      value.fail(fmt::format("targets file '{}' does not exist", file.string()));
    own = io::parse_yaml_file(file);
  } else if (value.is_map()) {
    own = raw;
  } else {
    value.fail_expected("a targets file name or a mapping (docs/tuning.md)");
  }
  for (const auto& entry : own)
    targets[entry.first.as<std::string>()] = YAML::Clone(entry.second);
  return targets;
}

} // namespace

StudySpec load_study(const std::filesystem::path& file,
                     const std::vector<std::string>& geometry_options) {
  StudySpec s;
  s.file = std::filesystem::absolute(file).lexically_normal();
  const std::filesystem::path dir = s.file.parent_path();
  const YAML::Node root_node = io::parse_yaml_file(file);
  const io::YamlValue root(file.string(), root_node);
  root.check_keys({"name", "case", "output", "ranks", "launcher", "time", "geometry", "tuning",
                   "png", "compare_rigid", "rom_sweep", "variants"});
  s.name = root.has("name") ? root.require("name", "").text() : file.stem().string();
  if (!is_folder_name(s.name))
    root.require("name", "")
        .fail_expected("a name of letters, digits, '_', '-' and '.', other than '.' and '..'");
  const io::YamlValue case_value = root.require("case", "the template case file (docs/study.md)");
  s.case_file = io::resolve_path(dir, case_value.text());
  if (!std::filesystem::exists(s.case_file))
    case_value.fail(fmt::format("case file '{}' does not exist", s.case_file.string()));
  s.output = std::filesystem::absolute(
      root.has("output") ? std::filesystem::path(root.require("output", "").text())
                         : std::filesystem::path("results") / s.name);
  if (const auto ranks = root.get("ranks"))
    s.ranks = ranks->integer(1);
  if (const auto launcher = root.get("launcher")) {
    s.launcher = launcher->text();
    if (s.launcher.find("{ranks}") == std::string::npos)
      launcher->fail_expected("a command with '{ranks}' where the number of ranks goes");
  }
  if (const auto time = root.get("time")) {
    time->check_keys({"cycles", "periodicity"});
    if (time->has("cycles") && time->has("periodicity"))
      time->fail("give `cycles` or `periodicity`, not both");
    if (const auto cycles = time->get("cycles"))
      cycles->integer(1);
    s.time = YAML::Clone(root_node["time"]);
  }
  if (const auto png = root.get("png"))
    s.png = png->choice({"true", "false"}) == "true";
  if (const auto rigid = root.get("compare_rigid")) {
    s.compare_rigid = rigid->choice({"true", "false"}) == "true";
    if (s.compare_rigid && !io::parse_yaml_file(s.case_file)["solid"])
      rigid->fail("the case has rigid walls already (no `solid` section): nothing to compare");
  }
  if (const auto rom = root.get("rom_sweep")) {
    rom->check_keys({"entry", "exit", "steps"});
    StudySpec::RomSweep r;
    for (const char* key : {"entry", "exit"}) {
      const io::YamlValue v = rom->require(key, "tear areas MIN:MAX in mm^2, e.g. 30:300");
      const std::string text = v.text();
      const auto colon = text.find(':');
      double lo = 0, hi = 0;
      if (colon == std::string::npos || std::sscanf(text.c_str(), "%lf:%lf", &lo, &hi) != 2 ||
          !(lo > 0 && hi > lo))
        v.fail_expected("tear areas MIN:MAX in mm^2 with 0 < MIN < MAX, e.g. 30:300");
      (std::string(key) == "entry" ? r.entry : r.exit) = text;
    }
    if (const auto steps = rom->get("steps"))
      r.steps = steps->integer(2);
    s.rom_sweep = r;
  }
  std::map<std::string, std::string> geometry_defaults;
  if (const auto g = root.get("geometry"))
    read_geometry(*g, geometry_options, geometry_defaults);
  const YAML::Node tuning_defaults = root_node["tuning"];
  if (const auto t = root.get("tuning"); t && !t->is_map())
    t->fail_expected("a mapping of targets-file keys shared by the variants (docs/tuning.md)");

  const io::YamlValue list = root.require("variants", "a list of variants (docs/study.md)");
  const std::vector<io::YamlValue> items = list.items();
  for (std::size_t i = 0; i < items.size(); ++i) {
    const io::YamlValue& item = items[i];
    item.check_keys({"name", "geometry", "model", "targets"});
    Variant v;
    const io::YamlValue name = item.require("name", "the variant's name");
    v.name = name.text();
    if (!is_folder_name(v.name)) // '..' would write into the study's parent folder
      name.fail_expected("a name of letters, digits, '_', '-' and '.', other than '.' and '..' "
                         "(it names a folder)");
    for (const Variant& other : s.variants)
      if (other.name == v.name)
        name.fail(fmt::format("variant '{}' is given twice", v.name));
    if (item.has("geometry") && item.has("model"))
      item.fail("give `geometry` (a recipe) or `model` (an imported model folder), not both");
    if (const auto model = item.get("model")) {
      v.model = io::resolve_path(dir, model->text());
      const GeometryFiles folder{*v.model};
      for (const std::filesystem::path& needed : {folder.mesh(), folder.landmarks()})
        if (!std::filesystem::exists(needed))
          model->fail(fmt::format("'{}' has no {} (a folder written by `tearflow geometry`)",
                                  v.model->string(), needed.filename().string()));
    } else {
      v.geometry = geometry_defaults;
      if (const auto g = item.get("geometry"))
        read_geometry(*g, geometry_options, v.geometry);
    }
    if (const auto targets = item.get("targets"))
      v.targets = read_targets(*targets, root_node["variants"][i]["targets"], dir, tuning_defaults);
    s.variants.push_back(std::move(v));
  }
  if (s.variants.empty())
    list.fail_expected("at least one variant");
  return s;
}

std::string fingerprint(const StudySpec& study, const Variant& v) {
  std::string text = v.name + "\n";
  for (const auto& [key, value] : v.geometry)
    text += key + "=" + value + "\n";
  if (v.model)
    text += "model=" + v.model->string() + "\n";
  if (given(v.targets))
    text += "targets=" + YAML::Dump(v.targets) + "\n";
  if (given(study.time))
    text += "time=" + YAML::Dump(study.time) + "\n";
  text += "case=" + read_text(study.case_file);
  // The basis is a digit short of FNV's 14695981039346656037; kept, so that the stages
  // recorded in existing study.json files still match their fingerprints.
  return fmt::format("{:016x}", fnv1a(text.data(), text.size(), 1469598103934665603ULL));
}

} // namespace tearflow::study
