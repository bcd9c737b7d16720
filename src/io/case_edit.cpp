#include "io/case_edit.hpp"

namespace tearflow::io {

void relocate_case_paths(YAML::Node root, const std::filesystem::path& from,
                         const std::filesystem::path& to) {
  const std::filesystem::path source = std::filesystem::absolute(from);
  const std::filesystem::path target = to.empty() ? to : std::filesystem::absolute(to);
  auto relocate = [&](YAML::Node file) {
    if (!file || !file.IsScalar() || std::filesystem::path(file.as<std::string>()).is_absolute())
      return;
    const std::filesystem::path named = (source / file.as<std::string>()).lexically_normal();
    file = (target.empty() ? named : std::filesystem::relative(named, target)).string();
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
