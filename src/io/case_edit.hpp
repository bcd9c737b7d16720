#pragma once
// Writing a case file somewhere else (a tuned case, a study's variants, a rigid-wall copy):
// the one place that knows which keys of a case are file paths, so that an edited copy
// finds the same files wherever it is written.
#include <filesystem>

#include <yaml-cpp/yaml.h>

namespace tearflow::io {

/// Rewrites the relative file paths of a case document read from the folder `from` (mesh.file,
/// mesh.wall_file, and the `file` of every waveform of the fluid's and the wall's boundary
/// conditions) so that the document, written into the folder `to`, names the same files:
/// relative to `to`, or absolute when `to` is empty. Absolute paths are left as written.
void relocate_case_paths(YAML::Node root, const std::filesystem::path& from,
                         const std::filesystem::path& to = {});

} // namespace tearflow::io
