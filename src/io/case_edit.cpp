#include "io/case_edit.hpp"

#include "io/case_yaml.hpp"

namespace tearflow::io {

void relocate_case_paths(YAML::Node root, const std::filesystem::path& from,
                         const std::filesystem::path& to) {
  const std::filesystem::path source = std::filesystem::absolute(from).lexically_normal();
  const std::filesystem::path target =
      to.empty() ? to : std::filesystem::absolute(to).lexically_normal();
  auto relocate = [&](YAML::Node file) {
    if (!file || !file.IsScalar() || std::filesystem::path(file.as<std::string>()).is_absolute())
      return;
    const std::filesystem::path named = resolve_path(source, file.as<std::string>());
    // Lexically, as the case reader joins paths (resolve_path): std::filesystem::relative
    // would resolve symlinks on one side only, and a case in a symlinked folder lose its files.
    const std::filesystem::path relative =
        target.empty() ? std::filesystem::path() : named.lexically_relative(target);
    file = (relative.empty() ? named : relative).string();
  };
  if (root["mesh"] && root["mesh"].IsMap())
    for (const char* key : {"file", "wall_file"})
      relocate(root["mesh"][key]);
  // The waveforms of docs/case-file.md: an inflow's flow, an outlet's pressure, a wall's load.
  YAML::Node solid = root["solid"];
  for (YAML::Node list : {root["boundary_conditions"],
                          solid && solid.IsMap() ? solid["boundary_conditions"] : YAML::Node()})
    if (list && list.IsSequence())
      for (YAML::Node item : list)
        for (const char* key : {"flow", "pressure"})
          if (item[key] && item[key].IsMap())
            relocate(item[key]["file"]);
}

} // namespace tearflow::io
