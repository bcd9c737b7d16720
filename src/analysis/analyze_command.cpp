#include "analysis/analyze_command.hpp"

#include <fmt/format.h>

#include "analysis/hemodynamics.hpp"
#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "core/units.hpp"

namespace tearflow::analysis {

AnalyzeCommand::AnalyzeCommand(CLI::App& app) {
  command_ = app.add_subcommand("analyze", "flow, area and pressure at the landmark planes of a "
                                           "run (docs/analysis.md)");
  command_->add_option("run_dir", run_dir_, "output directory of `tearflow run`")->required();
  command_->add_option("--landmarks", landmarks_,
                       "landmarks JSON (default RUN_DIR/geometry/landmarks.json)");
  command_
      ->add_option("--cycle", cycle_,
                   "cardiac cycle as numbered in cycles.json (default: "
                   "the last complete one)")
      ->check(CLI::Range(1, 1000000));
  command_
      ->add_option("--frames", frames_,
                   "'cycle' (a complete cardiac cycle) or 'all' (every saved frame, no "
                   "cycle needed)")
      ->check(CLI::IsMember({"cycle", "all"}));
  command_->add_option("-o,--output", output_, "output directory (default RUN_DIR/analysis)");
  command_->add_option("--case", case_file_,
                       "the run's case file: its fluid and time step give the conservative "
                       "flux (default: tuned.yaml or case.yaml beside RUN_DIR writing to it)");
  command_->add_flag("-q,--quiet", quiet_, "no summary lines");
}

int AnalyzeCommand::run() const {
  AnalyzeOptions o;
  o.run_dir = run_dir_;
  o.landmarks = landmarks_;
  if (cycle_ > 0)
    o.cycle = cycle_;
  o.all_frames = frames_ == "all";
  o.case_file = case_file_;
  if (o.all_frames && o.cycle)
    input_error("analyze: --cycle and --frames all exclude each other");
  o.output = output_.empty() ? RunFiles{o.run_dir}.analysis_dir() : std::filesystem::path(output_);
  const Analysis a = analyze_run(o);
  write_analysis(a, o.output);
  if (!quiet_) {
    fmt::print("analyze '{}': {}, {} frames (t = {} to {} s), {} landmarks; peak systole at "
               "t = {} s\n",
               o.run_dir.string(), a.frames, a.time.size(), a.time.front(), a.time.back(),
               a.series.size(), a.time[a.peak_systole]);
    fmt::print("{:<10} {:>5} {:>14} {:>10} {:>12}\n", "landmark", "lumen", "Qmean [mL/s]",
               "A0 [mm2]", "Pmean [mmHg]");
    const nlohmann::json m = metrics_json(a);
    for (const LandmarkSeries& s : a.series) {
      const nlohmann::json& l = m["landmarks"][s.landmark.name];
      fmt::print("{:<10} {:>5} {:>14.3f} {:>10.2f} {:>12.2f}\n", s.landmark.name, s.landmark.lumen,
                 l["mean_flow_m3_per_s"].get<double>() / units::mL, l["A_0_mm2"].get<double>(),
                 l["mean_pressure_mmHg"].get<double>());
    }
    fmt::print("results in '{}'\n", o.output.string());
  }
  return 0;
}

} // namespace tearflow::analysis
