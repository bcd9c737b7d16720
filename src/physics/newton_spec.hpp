#pragma once
// When a Newton iteration of a time step stops: the settings every stepper takes (fluid, FSI,
// wall alone). The case file's `newton` section fills it (docs/case-file.md).

namespace tearflow::physics {

// Each field is tested against its own scale (fluid_solver.cpp): the momentum rows (and a
// wall's volume constraint) relative to their largest residual in the step, the continuity rows, a
// flow rate per node [m^3/s], against the inflow: their sum of magnitudes bounds the mass that any
// set of nodes, the volume between two landmark planes among them, fails to conserve.
struct NewtonSpec {
  int max_iterations = 10;
  double rtol = 1e-6;  ///< stop when each field's ||R|| <= rtol max_k ||R_k|| ...
  double atol = 1e-10; ///< ... or <= atol
  /// ... and the continuity rows' ||R||_1 <= continuity times the inflow's peak |Q|
  /// (without an inflow, relative as the momentum).
  double continuity = 1e-3;
};

/// Where a problem's fields sit in its node block, for that test.
struct ResidualFields {
  int continuity = 3;      ///< slot of the fluid's continuity rows
  int constraint = -1;     ///< slot of a wall's volume constraint rows; -1: none
  double flow_scale = 0.0; ///< the inflow's peak |Q| [m^3/s]; 0: no inflow
};

} // namespace tearflow::physics
