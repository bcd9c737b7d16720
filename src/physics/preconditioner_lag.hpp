#pragma once
// When Newton's lagged preconditioner is built anew (NewtonStepper, fluid_solver.cpp).
//
// A preconditioner built from one Jacobian serves the next ones while the operator changes
// little: PETSc's -snes_lag_preconditioner L builds it every L Jacobians. It goes stale fastest
// where the flow changes fastest: on the 4.5 mm dissection's FSI in early systole (dt 20 ms,
// L = 10) the Krylov count per step grew 47, 99, 160, 217, 276 over the first five steps, and
// with one built at every Jacobian it stayed at 43-55 (docs/performance.md, 2026-11-28). So a
// solve that took more than `growth` times the iterations of the first solve after the build
// also builds one; the first solve's count is taken as at least kMinIterations, below which a
// build (about ten Krylov iterations' worth there) costs more than the growth. (Where Newton
// keeps its Jacobian, no Jacobian is assembled and the preconditioner stays: the counts are
// those seen at the Jacobians assembled, the first of them after the build the reference.)
//
// The counts are the build's own, and a checkpoint asks for a build (rebuild_next), so a run
// restarted from it takes the same decisions as the uninterrupted one.

#include <algorithm>

namespace tearflow::physics {

class PreconditionerLag {
public:
  static constexpr int kMinIterations = 10;

  /// lag: build every this many Jacobians (< 1: only when asked or grown); growth: 0 (off)
  /// or a factor above 1.
  PreconditionerLag(int lag, double growth) : lag_(lag), growth_(growth) {}

  /// The next Jacobian builds the preconditioner (a run's first, after a checkpoint, a
  /// retried step).
  void rebuild_next() { rebuild_ = true; }
  bool rebuild_pending() const { return rebuild_; }
  int lag() const { return lag_; }

  /// Called for each Jacobian assembled, with the Krylov iterations of the linear solve before
  /// it (any value where none was made since the last build): whether this Jacobian builds the
  /// preconditioner.
  bool due(int last_iterations) {
    if (!rebuild_ && since_build_ == 1)
      first_iterations_ = last_iterations; // the first solve with this build
    const bool grown = growth_ > 0.0 && since_build_ > 1 &&
                       last_iterations > growth_ * std::max(first_iterations_, kMinIterations);
    const bool is_due = rebuild_ || grown || (lag_ > 0 && since_build_ >= lag_);
    rebuild_ = false;
    since_build_ = is_due ? 1 : since_build_ + 1;
    return is_due;
  }

private:
  int lag_;
  double growth_;
  bool rebuild_ = true;
  int since_build_ = 0;      ///< Jacobians since the last build, that one included
  int first_iterations_ = 0; ///< the first solve's after the build
};

} // namespace tearflow::physics
