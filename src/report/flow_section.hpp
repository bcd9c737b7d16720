#pragma once
// The "Flow patterns" section of the report pages (issue 30): the pictures `tearflow
// pictures` made of each run (RUN_DIR/analysis/figures/flow/, pictures.json), embedded in the
// page as PNG data so that it stays one self-contained file; on a comparison page the runs
// side by side, one column each, picture by picture.
#include <filesystem>
#include <string>
#include <vector>

namespace tearflow::report {

/// The folder `tearflow pictures` writes into by default.
std::filesystem::path flow_pictures_dir(const std::filesystem::path& run_dir);

/// The section for `run_dirs` (their names as the page shows them): every picture of the
/// first frame (peak systole, or the frame asked for) of each run that has pictures, in the
/// order of the first such run; empty when none has. InputError naming pictures.json when
/// it is not valid JSON.
std::string flow_patterns_section(const std::vector<std::filesystem::path>& run_dirs,
                                  const std::vector<std::string>& names);

/// Copies the PNGs of each run's pictures (every frame's, the model's and the animation; not
/// the animation's single frames) into FIGURES/flow/<name>/ (spaces in the name as '_'), the
/// layout of the pictures folder kept, beside the page's own figures. Returns the count;
/// InputError naming the file a copy fails on (a full disk).
std::size_t copy_flow_pictures(const std::vector<std::filesystem::path>& run_dirs,
                               const std::vector<std::string>& names,
                               const std::filesystem::path& figures);

} // namespace tearflow::report
