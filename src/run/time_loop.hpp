#pragma once
// The one time loop of every run, whatever its model (run/model.hpp): the start (fresh, a
// restart from the run's own checkpoint, or another run's state), then per step the step
// itself, the record of the faces, the cycle's statistics and the periodicity stop, frames,
// checkpoints and a progress line with its ETA. A step that fails keeps the record and the
// last good checkpoint, and says where and when.
#include <filesystem>
#include <functional>
#include <vector>

#include "physics/step_report.hpp"
#include "run/cycle_summary.hpp"

namespace tearflow::run {

class Model;

struct RunOptions {
  bool restart = false; ///< continue from the output directory's checkpoint
  /// A checkpoint (of this case, perhaps at another time step) whose state starts a new run
  /// at its time, e.g. a finer step from a periodic state; empty: the case's own start.
  std::filesystem::path start_from;
  /// The case of the run that wrote `start_from`, when its mesh is another one than this
  /// case's: the state is interpolated to this mesh (fem/node_transfer.hpp).
  std::filesystem::path start_case;
  bool progress = true; ///< one progress line per step on stdout
  bool write_output = true;
  /// Called at the end of every cycle with its statistics and whether it is periodic by the
  /// case's tolerance, before the cycle's last frame and checkpoint are written; returns
  /// whether the run stops there. Without it the run stops when periodic.
  std::function<bool(const run::CycleStats&, bool periodic)> on_cycle;
};

struct RunSummary {
  int steps = 0; ///< steps taken by this call
  double wall_seconds = 0.0;
  std::vector<physics::StepReport> reports;
  bool periodic = false;               ///< stopped by the periodicity tolerance
  std::vector<run::CycleStats> cycles; ///< every complete cycle of the run
};

/// Runs `model` from its state to the case's last step (or its periodicity stop), writing the
/// run directory (docs/outputs.md) unless options.write_output is off.
RunSummary run_loop(Model& model, const RunOptions& options);

} // namespace tearflow::run
