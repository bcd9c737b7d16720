#pragma once
// A run that tunes its own outlets: the 3D correction of outlet_tuning.hpp applied at the end
// of every cycle of the one run that is analysed, instead of in separate runs from rest.
//
//   cycle 1 runs the 0D stage's outlets from the 0D periodic start;
//   at the end of cycle k the cycle is measured (inlet P_sys, P_dias, MAP; splits; outlet
//   means) and scored against the targets;
//     met and periodic (the case's time.periodicity tolerance) -> the run stops: cycle k is
//                                                                 the tuned, periodic cycle;
//     every error within half its tolerance, not yet periodic  -> the outlets stay;
//     otherwise                                                -> learn (steps a-c), refit,
//        and cycle k+1 runs the new outlets, each outlet's distal pressure scaled by the
//        ratio of the new to the old outlets' 0D periodic distal pressure at the cycle
//        start (both behind the domain just measured), so that the new outlets start near
//        their own periodic state.
//
// Why: a compliant wall's run costs minutes per cycle, and a separate correction run must
// start from rest and cycle again to periodicity; here every cycle serves both the
// correction and the approach to periodicity (docs/tuning.md). The run's folder gets
// tuning.json (every step, the cycle it ran from) and tuned.yaml (the case with the outlets
// of the last cycle); a restart (--restart) takes the outlets that ran at the checkpoint.
#include <filesystem>
#include <vector>

#include "run/simulation.hpp"
#include "tuning/outlet_tuning.hpp"

namespace tearflow::tuning {

struct CorrectedRun {
  run::RunSummary summary;
  std::vector<TuningStep> steps; ///< the 0D stage, then one measured step per cycle
  bool met = false;              ///< the last cycle meets the targets
};

/// Runs `c` (the case file `case_file`, for the tuned case written beside the results) with
/// outlets corrected at cycle ends until a periodic cycle meets `targets`, or the case's
/// steps run out. `targets_file` names the targets in the written headers.
CorrectedRun run_corrected(const io::Case& c, const std::filesystem::path& case_file,
                           const TuningTargets& targets, const std::filesystem::path& targets_file,
                           run::RunOptions options);

} // namespace tearflow::tuning
