#pragma once
// Calibration of the reduced-order model against 3D runs of the same geometry (`rom
// calibrate`): the few coefficients the network cannot know from the geometry (the tears'
// loss coefficients K_t, the viscous factor alpha, the lumina's friction factor f, the arch's
// loss K_arch, for compliant walls the flap's compliance factor beta, and, when the runs hold
// a tear at two sizes, the tears' size exponent gamma; rom/dissection_network.hpp) are fitted
// by Levenberg-Marquardt in their logarithms (so they stay positive; gamma as is) to what the
// runs' analyses measured over their analysed cycle, on the 3D frames' times:
//   - at every paired station k, dP_k(t) = P_TLk - P_FLk                      [per mmHg],
//   - the drops inlet -> FL1 (entry), FL5 -> outlet (exit), inlet -> DAo_prox  [per mmHg],
//   - the FL flow ratio at every station                                       [per 0.5 point],
// so one point of FR_FL weighs as 2 mmHg (the accuracy the study asks: 5 points, 3 mmHg).
// Rigid and compliant runs are fitted separately (the flap's factor is only seen with a
// wall); calibration.json in MODEL/rom holds both, each with the runs and residuals.
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/hemodynamics.hpp"
#include "rom/dissection_network.hpp"

namespace tearflow::rom {

/// One 3D run: its case's inputs and its analysis' landmark series (t from the cycle start).
struct CalibrationRun {
  std::string name;
  RomInputs inputs;
  std::map<std::string, double> tear_areas;        ///< the run's own tears [m^2] where they differ
  std::vector<double> time;                        ///< [s] from the analysed cycle's start
  std::map<std::string, std::vector<double>> flow; ///< by landmark [m^3/s]
  std::map<std::string, std::vector<double>> pressure; ///< by landmark [Pa]
};

/// Reads RUN_DIR/analysis/<landmark>.csv (written by `analyze`). InputError naming the file
/// and line for a missing file or column, or a number that is not one.
/// `run_model`, when given, is the run's own model directory: its tears' areas replace the
/// calibrated model's (a run of another tear-size variant of the same geometry).
CalibrationRun read_calibration_run(const std::filesystem::path& run_dir, const io::Case& c,
                                    const DissectionGeometry& g, double wall_thickness,
                                    const std::filesystem::path& run_model = {});

/// The misfit of a prediction against a run: the residual vector (file comment's weights).
std::vector<double> misfit(const analysis::Analysis& predicted, const CalibrationRun& run);

struct CalibrationFit {
  bool compliant = false;
  RomCoefficients coefficients;
  std::vector<std::string> runs;
  double rms_before = 0.0, rms_after = 0.0; ///< of the weighted residuals
  int evaluations = 0;
};

struct Calibration {
  std::optional<CalibrationFit> rigid, compliant;
};

/// Fits each wall model's coefficients to its runs (file comment); `progress` prints them.
/// `fit`, when not empty, names the coefficients to fit (viscous, arch, friction, tears, flap,
/// size); the others keep their defaults.
Calibration calibrate_model(const DissectionGeometry& g, const geometry::Landmarks& landmarks,
                            const std::vector<CalibrationRun>& runs,
                            const IntegrationOptions& options, bool progress,
                            const std::set<std::string>& fit = {});

/// Writes MODEL/rom/calibration.json, keeping a wall model's earlier fit that this one lacks.
void save_calibration(const std::filesystem::path& model_dir, const Calibration& c);

/// Whether MODEL/rom/calibration.json is there and of this tearflow's network (a fit made for
/// an earlier one is refused by load_coefficients).
bool calibration_is_current(const std::filesystem::path& model_dir);

/// The coefficients for a wall model: from `file` if given, else MODEL/rom/calibration.json
/// (the other wall model's fit when its own is missing, said when `progress`), else the
/// uncalibrated defaults (said when `progress`).
RomCoefficients load_coefficients(const std::filesystem::path& model_dir,
                                  const std::filesystem::path& file, bool compliant, bool progress);

/// FR_FL and peak-systolic / end-diastolic dP per station, the inlet's pressures (stdout).
void print_summary(const analysis::Analysis& a);

} // namespace tearflow::rom
