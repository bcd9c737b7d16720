#pragma once
// Built-in verification cases: each runs a problem whose answer is known independently of
// the code and reports its error metrics against tolerances derived from the method's
// expected accuracy. `tearflow verify NAME` prints the result as one JSON object.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tearflow::verify {

struct Metric {
  std::string name;
  double value = 0.0;
  double tolerance = 0.0;                            ///< pass when value <= tolerance
  std::string meaning;                               ///< what is measured and why the tolerance
  bool passed() const { return value <= tolerance; } ///< false for a NaN value
};

/// max(worst, x) that keeps a NaN: a NaN error (a diverged run, a missing sample) must fail
/// the metric, where std::max(worst, NaN) would silently return worst.
inline double worst_of(double worst, double x) {
  return std::isnan(worst) || std::isnan(x) ? std::numeric_limits<double>::quiet_NaN()
                                            : std::max(worst, x);
}

struct VerificationResult {
  std::string name;
  std::vector<Metric> metrics;
  nlohmann::json details; ///< supporting numbers: meshes, sizes, rates, samples
  bool passed() const;
  nlohmann::json to_json() const;
};

struct VerifyOptions {
  bool convergence = false; ///< also run the refinement study
  bool progress = false;    ///< per-step progress lines on stderr
  /// Scales the mesh size: > 1 coarsens (the reduced form CI runs), 1 is the default mesh.
  double coarsening = 1.0;
  /// Directory for a case's time series (CSV), created if missing; empty: none written.
  std::string output;
  /// CI's short form of a case that a coarser mesh cannot shorten (pulse: the time step
  /// doubled, the solver checked against its continuum only); ignored by the other cases.
  bool reduced = false;
};

struct VerificationCase {
  std::string description;
  std::function<VerificationResult(const VerifyOptions&)> run;
};

const std::map<std::string, VerificationCase>& verification_cases();

} // namespace tearflow::verify
