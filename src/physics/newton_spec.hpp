#pragma once
// When a Newton iteration of a time step stops: the settings every stepper takes (fluid, FSI,
// wall alone). The case file's `newton` section fills it (docs/case-file.md).

namespace tearflow::physics {

struct NewtonSpec {
  int max_iterations = 10;
  double rtol = 1e-6;  ///< stop when ||R|| <= rtol ||R_0|| ...
  double atol = 1e-10; ///< ... or ||R|| <= atol
};

} // namespace tearflow::physics
