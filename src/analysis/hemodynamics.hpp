#pragma once
// `tearflow analyze`: the reference study's quantities at the landmark planes of a run
// (../shared/reference/tbad-study.md, "Quantities the study reports"), over the last
// complete cardiac cycle, a chosen one, or every saved frame:
//   - per landmark (lumen): Q(t), A(t), P(t), max u.n(t); net flow volume int Q dt; A_0 (first
//     frame, end diastole), A_max, A_mean, A(t) / A_0;
//   - per paired station k: FR_FL = Qbar_FL / (Qbar_FL + Qbar_TL) * 100 with cycle-mean flows,
//     dP(t) = P_TLk - P_FLk and its peak-systolic and end-diastolic values;
//   - peak-systolic pressure at inlet, TLk, FLk and outlet over the inlet's; pressure drops
//     inlet -> FL1 (entry tear), FL5 -> outlet (exit tear), inlet -> outlet;
//   - flow conservation: Q_TLk + Q_FLk against DAo_prox / DAo_dist at every frame.
// Peak systole is the frame of largest flow through the `inlet` landmark (the first landmark
// when there is none); end diastole the first frame. Time means and volumes use the
// trapezoidal rule over the frames, as cycles.json does.
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/landmark_sections.hpp"
#include "geometry/landmarks.hpp"

namespace tearflow::analysis {

struct AnalyzeOptions {
  std::filesystem::path run_dir;
  std::filesystem::path landmarks; ///< empty: RUN_DIR/geometry/landmarks.json
  std::optional<int> cycle;        ///< as numbered in cycles.json; none: the last complete one
  bool all_frames = false;         ///< every saved frame, no complete cycle needed
  std::filesystem::path output;    ///< empty: RUN_DIR/analysis
  /// The run's case, for the conservative flux (analysis/run_form.hpp); empty: looked for
  std::filesystem::path case_file;
};

/// One landmark's section values over the frames.
struct LandmarkSeries {
  geometry::Landmark landmark;
  std::vector<SectionValues> samples; ///< per frame
};

struct Analysis {
  std::string source = "simulation"; ///< or "measured" (analysis/measured_data.hpp)
  std::string frames;                ///< what was analysed, e.g. "cycle 3" or "all saved frames"
  /// How Q was measured: "conservative" (the solver's conserved flux), "plane_integral" (of
  /// the interpolated velocity; the run's case was not found) or "measured".
  std::string flow_method = "measured";
  /// Of the conservative flows, how many came from their step's stage (balanced to the
  /// Newton tolerance; the others are estimates from one frame, analysis/conservative_flux).
  std::size_t stage_frames = 0;
  std::vector<double> time; ///< per frame [s]
  std::vector<LandmarkSeries> series;
  std::size_t peak_systole = 0; ///< frame index
  std::size_t end_diastole = 0; ///< frame index (the first)
  /// The analysed cycle's entry of the run's cycles.json (face pressures and flow splits);
  /// null for every-frame analyses and measurements.
  nlohmann::json cycle;

  /// The series of landmark `name`, nullptr if there is none.
  const LandmarkSeries* find(const std::string& name) const;
};

/// The frames to analyse (cycle choice above); InputError naming cycles.json or the .pvd
/// when there is no complete cycle, the chosen one does not exist or holds < 2 frames.
/// `cycle`, when given, receives the chosen cycle's entry of cycles.json.
std::vector<FlowFrame> select_frames(const AnalyzeOptions& options, std::string& label,
                                     nlohmann::json* cycle = nullptr);

/// Reads the frames and measures every landmark of each (see measure_landmarks); a folder of
/// measurement tables instead of a run is read by read_measured (analysis/measured_data.hpp).
Analysis analyze_run(const AnalyzeOptions& options);

/// The time mean of f over the frames t by the trapezoidal rule (as cycles.json's); a single
/// frame is its own mean.
double time_mean(const std::vector<double>& t, const std::vector<double>& f);

/// Linear interpolation of (t, f) at `at` (t increasing), holding the end values outside
/// [t0, tn].
double interpolate(const std::vector<double>& t, const std::vector<double>& f, double at);

/// Sets peak systole (largest flow through `inlet`, else through the first landmark with a
/// measured flow) and end diastole (the first frame).
void mark_cycle_events(Analysis& analysis);

/// The headline numbers; every key names its unit.
nlohmann::json metrics_json(const Analysis& analysis);

/// Writes metrics.json, one CSV per landmark (`<name>.csv`) and, when there are paired
/// stations, `pressure_difference.csv` into `directory`.
void write_analysis(const Analysis& analysis, const std::filesystem::path& directory);

/// A landmark's CSV as write_analysis writes it: its columns by name, in the file's order
/// (a value may be nan, as written for what a run does not know).
struct LandmarkTable {
  std::filesystem::path file;
  std::vector<std::string> names;
  std::map<std::string, std::vector<double>> columns;
  /// The column called `name`; InputError naming the file otherwise.
  const std::vector<double>& column(const std::string& name) const;
};

/// Reads a landmark's CSV; InputError naming the file (and the line and column) when it
/// cannot be read, a row has another number of columns than the header, or a cell is not a
/// number.
LandmarkTable read_landmark_table(const std::filesystem::path& csv);

} // namespace tearflow::analysis
