#pragma once
// Stage 1 of outlet tuning: the Windkessel totals (R_T, C_T, k_d) that make the 0D model of
// the outlets (bc/windkessel_network.hpp) reproduce measured inlet pressures.
//
// As in the reference study (../shared/reference/tbad-study.md) the totals are distributed
// over the outlets by their measured flow fractions f_i:
//   R_i = R_T / f_i,  R_p,i = (1 - k_d) R_i,  R_d,i = k_d R_i,  C_i = C_T f_i,
// so every outlet has the same time constant k_d R_T C_T and the mean flow splits as f_i
// (per-outlet parameters: the domain's branch resistances are subtracted, see distribute).
// The fit is a nonlinear least-squares problem in three unknowns for the three targets
// (systolic, diastolic, mean inlet pressure), solved by Levenberg-Marquardt (Eigen's MINPACK
// port) in the variables (ln (R_T - R_min), ln C_T, logit k_d), which keeps every parameter
// in range (R_min = max_i e_i f_i, 0 without branch resistances).
#include <string>
#include <vector>

#include "bc/waveform.hpp"
#include "bc/windkessel_network.hpp"

namespace tearflow::tuning {

struct OutletFraction {
  std::string face;
  double fraction = 0.0; ///< f_i, share of the total outflow, in (0, 1]
};

struct WindkesselTotals {
  double resistance = 0.0;   ///< R_T [Pa s/m^3]
  double capacitance = 0.0;  ///< C_T [m^3/Pa]
  double distal_share = 0.0; ///< k_d in (0, 1)
};

struct InletPressures {
  double systolic = 0.0, diastolic = 0.0, mean = 0.0; ///< [Pa]
};

/// What the 0D model knows of the 3D domain between the inlet and the outlets: resistances
/// measured from a 3D run (mean pressure drop over mean flow) or given.
struct DomainResistance {
  double series = 0.0;        ///< between the inlet and the outlets' common node [Pa s/m^3]
  std::vector<double> branch; ///< e_i, in series with outlet i's RCR; empty: none [Pa s/m^3]
  double of_branch(size_t i) const { return branch.empty() ? 0.0 : branch[i]; }
};

/// The outlets' RCRs from the totals (P_ref = 0). With branch resistances e_i, R_T / f_i is
/// the resistance of branch i as a whole, so the outlet's own is R_i = R_T / f_i - e_i
/// (per-outlet parameters; R_T must exceed max_i e_i f_i): the mean flow still splits as f_i.
std::vector<bc::WindkesselBranch> distribute(const WindkesselTotals& totals,
                                             const std::vector<OutletFraction>& outlets,
                                             const DomainResistance& domain = {});

/// The 0D model of the case: the outlets' RCRs behind the domain's resistances.
bc::WindkesselNetwork zero_d_model(const std::vector<bc::WindkesselBranch>& outlets,
                                   const DomainResistance& domain);

/// Systolic, diastolic and mean inlet pressure of the 0D model's periodic state.
InletPressures inlet_pressures(const bc::PeriodicState& state);
InletPressures inlet_pressures(const bc::WindkesselNetwork& network, const bc::Waveform& inflow);

struct FitResult {
  WindkesselTotals totals;
  InletPressures achieved;
  double max_relative_error = 0.0; ///< over the three pressures
  int evaluations = 0;
};

/// Fits the totals to the targets for the inflow Q_in(t) (periodic, positive mean) with the
/// 3D domain's resistances `domain` in the 0D model. `start` is the initial guess; a zero
/// start means the default R_T = MAP / mean(Q) - series, C_T = T / R_T (T the period),
/// k_d = 0.85; starts with R_T C_T of 0.3, 1 and 3 periods follow.
/// InputError when the targets are inconsistent (P_dias >= MAP >= P_sys, mean flow <= 0).
FitResult fit_windkessel_totals(const InletPressures& targets, const bc::Waveform& inflow,
                                const std::vector<OutletFraction>& outlets,
                                const DomainResistance& domain = {}, WindkesselTotals start = {});

} // namespace tearflow::tuning
