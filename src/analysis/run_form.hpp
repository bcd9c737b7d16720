#pragma once
// What a run's analysis needs to know of the solver that produced it: the fluid and the time
// step of its continuity equation, for the conservative flux (analysis/conservative_flux.hpp).
// A run's output folder does not hold them; its case file does.
#include <filesystem>
#include <optional>
#include <vector>

#include "analysis/conservative_flux.hpp"

namespace tearflow::analysis {

/// The run's continuity form: its case is `case_file` when given (InputError if it cannot be
/// read), else the case beside RUN_DIR whose output folder is RUN_DIR (a study's layout:
/// tuned.yaml, then case.yaml); none found: nullopt (the analysis then integrates the
/// interpolated velocity over the planes).
std::optional<ContinuityForm> find_continuity_form(const std::filesystem::path& run_dir,
                                                   const std::filesystem::path& case_file);

/// The times of the run's steps in RUN_DIR/faces.csv (every step is recorded there), in
/// order; empty without that file.
std::vector<double> step_times(const std::filesystem::path& run_dir);

/// The time step that ended at `time` (a saved frame's): from `times`, else `fallback`
/// (the case's step); nullopt for the run's initial state (the first time in `times`), which
/// no step solved, so that its fields satisfy no continuity equation.
std::optional<double> step_ending_at(const std::vector<double>& times, double time,
                                     double fallback);

} // namespace tearflow::analysis
