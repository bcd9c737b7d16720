#pragma once
// A study file (docs/study.md): variants of one case that differ in their geometry (a recipe
// for `tearflow geometry tbad`, or an imported model) and their tuning targets, run through
// the same stages and compared. Read and validated as a whole before any stage runs.
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace tearflow::study {

struct Variant {
  std::string name;
  /// `tearflow geometry tbad` options (without the leading "--"), study defaults merged in.
  std::map<std::string, std::string> geometry;
  /// An imported model instead: a folder with mesh.msh and landmarks.json (as `tearflow
  /// geometry import` or `geometry tbad` write it).
  std::optional<std::filesystem::path> model;
  /// The targets for `tearflow tune` (docs/tuning.md) with the study's tuning defaults
  /// merged in; null: the case's outlets are run as they are.
  YAML::Node targets;
};

struct StudySpec {
  std::filesystem::path file; ///< the study file, absolute
  std::string name;
  std::filesystem::path case_file; ///< the template case, absolute
  std::filesystem::path output;    ///< absolute
  int ranks = 1;
  std::string launcher = "mpirun -n {ranks}"; ///< how to start `ranks` > 1 processes
  /// Overrides of the case's `time` (cycles or periodicity), as YAML; null: the case's.
  YAML::Node time;
  bool png = true; ///< figures as PNG through headless Chromium
  /// Each variant of a compliant study also runs with rigid walls and the outlets its
  /// compliant run ended with, and the report overlays both (docs/study.md).
  bool compare_rigid = false;
  /// The reduced-order model's tear-size maps (docs/rom.md): after the variants, `rom
  /// calibrate` on every analysed run and `rom sweep` of the first variant's model over these
  /// ranges [mm^2, "MIN:MAX"], shown in the report; empty: none.
  struct RomSweep {
    std::string entry, exit;
    int steps = 20;
  };
  std::optional<RomSweep> rom_sweep;
  std::vector<Variant> variants;
};

/// True when `node` holds a value (a default-constructed YAML::Node converts to true).
inline bool given(const YAML::Node& node) {
  return node.IsDefined() && !node.IsNull();
}

/// Reads and validates `file`. InputError "study.yaml:LINE: key: what was expected" for
/// unknown keys, a missing case, duplicate or malformed variant names, unknown geometry
/// options (checked against `geometry_options`, the options `tearflow geometry tbad`
/// accepts) and targets files that do not exist.
StudySpec load_study(const std::filesystem::path& file,
                     const std::vector<std::string>& geometry_options);

/// A stable fingerprint (FNV-1a, hex) of what makes a variant's results: its geometry, model,
/// targets, the case file's text and the time overrides. A finished stage whose fingerprint
/// differs is run again.
std::string fingerprint(const StudySpec& study, const Variant& variant);

} // namespace tearflow::study
