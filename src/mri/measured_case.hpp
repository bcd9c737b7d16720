#pragma once
// Measured 2D phase-contrast flows to a case and its tuning targets (`tearflow mri inflow`,
// docs/mri.md): what the reference study took from its scans, written so that `tearflow tune`
// and `tearflow run` take them as they are.
//   - inflow.csv: the inlet's flow over one R-R interval sampled at the case's time step
//     (vessel_flow.hpp's periodic spline, the phase after the R wave kept), mL/s; the period
//     made a whole number of steps (the R-R interval in whole ms is one with a 1 ms step);
//   - case.yaml: the case with its inflow's `flow` reading that file (paths relocated), and
//     time.period set to it when the case names one;
//   - targets.yaml: the outlets' flow splits, % of the outflow, from the cycle-mean flows: every
//     rcr / resistance outlet of the case measured, or all but one when the inlet is (that one
//     takes what the inlet brings and the others do not carry off); with the measured
//     pressures, which 2D scans cannot give.
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mri/vessel_flow.hpp"

namespace tearflow::mri {

struct MeasuredFlows {
  std::filesystem::path case_file;
  std::optional<VesselFlow> inlet;               ///< name: free (the case's inflow face is used)
  std::vector<VesselFlow> outlets;               ///< name: the case's outlet face
  std::optional<std::array<double, 3>> pressure; ///< systolic, diastolic, mean [Pa]
};

struct OutletSplit {
  std::string face;
  double percent = 0.0;
  std::string source; ///< "measured" or "inflow minus the measured outlets"
};

/// Writes inflow.csv (with an inlet), case.yaml and (with outlets) targets.yaml into `dir`;
/// returns what was written for the command's summary and report. InputError naming the case
/// file and the face: no single inflow face, a measured face that is not a tunable outlet,
/// outlets missing, measured outlets carrying more than the inflow, outlets without pressures.
nlohmann::json write_measured_case(const MeasuredFlows& flows, const std::filesystem::path& dir);

/// The splits alone (for tests): see write_measured_case.
std::vector<OutletSplit> outlet_splits(const std::vector<std::string>& tunable_outlets,
                                       const std::optional<VesselFlow>& inlet,
                                       const std::vector<VesselFlow>& outlets,
                                       const std::string& where);

} // namespace tearflow::mri
