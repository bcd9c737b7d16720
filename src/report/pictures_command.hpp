#pragma once
// `tearflow pictures RUN_DIR [--model DIR | --landmarks FILE] [--time T] [--seed LANDMARK]
// [--speed-max M] [--displacement-max-mm D] [--animate] [--no-png] [--mri SCAN [--mri-align F]
// [--mri-align-surface]] [-o DIR]`: the flow-pattern
// figures of a run (issue 30, docs/analysis.md "Flow pictures"): streamlines at peak systole (or
// the frame nearest T) from standard views, plane maps at every landmark at peak systole and
// mid-diastole, the wall's displacement of an FSI run; the geometry as VTP beside the PNGs,
// and pictures.json saying what each file shows and on which colour scale, and flow.pvsm,
// the first frame as a ParaView state (paraview_state.hpp). With --mri, the
// same streamlines (same seeds and cameras) and plane maps (same views) from a 4D-flow scan,
// files prefixed "mri_" beside the run's.
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "report/scan_pictures.hpp"

namespace tearflow::report {

struct PicturesOptions {
  std::string run_dir, model_dir, landmarks, output, seed;
  double time = -1.0;             ///< [s]; < 0: peak systole (and mid-diastole for the planes)
  double speed_max = 1.5;         ///< top of the speed scale [m/s]
  double displacement_max = 2e-3; ///< top of the displacement scale [m]
  double seed_spacing = 0.0;      ///< [m]; 0: the seed section's equivalent diameter / 10
  bool png = true, quiet = false;
  /// Also the streamlines of every frame of the cycle as one animated PNG (first view with
  /// the tears face on, else anterior).
  bool animate = false;
  /// The views of the streamlines and the wall (chosen_views: standard names or NAME:X,Y,Z);
  /// empty: the standard ones.
  std::vector<std::string> views;
  /// A 4D-flow scan pictured beside the run (report/scan_pictures.hpp); scan.scan empty: none.
  ScanOptions scan;
};

/// Makes the pictures; returns the exit code. InputError for bad input (a missing run
/// folder, an unknown landmark, a time outside the run), naming the file or option.
int make_pictures(const PicturesOptions& options);

class PicturesCommand {
public:
  explicit PicturesCommand(CLI::App& app); ///< registers `pictures` on app
  bool selected() const { return command_->parsed(); }
  int run() const;

private:
  CLI::App* command_ = nullptr;
  PicturesOptions options_;
  double displacement_max_mm_ = 2.0, seed_spacing_mm_ = 0.0;
  bool no_png_ = false;
};

} // namespace tearflow::report
