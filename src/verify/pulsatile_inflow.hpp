#pragma once
// The inflow of the outlet verification cases: Q(t) = Q_mean (1 - cos wt)(1 + sin(wt)/2),
// two harmonics and a systolic peak of 3 Q_mean; zero at t = 0 where the 3D runs start from
// rest, so the 3D and 0D problems start alike. Sampled finely for the periodic spline.
#include <cmath>
#include <numbers>
#include <vector>

#include "bc/waveform.hpp"

namespace tearflow::verify {

inline bc::Waveform pulsatile_inflow(double q_mean, double period) {
  constexpr int samples = 200;
  std::vector<double> t, q;
  for (int k = 0; k < samples; ++k) {
    const double s = 2.0 * std::numbers::pi * k / samples;
    t.push_back(period * k / samples);
    q.push_back(q_mean * (1.0 - std::cos(s)) * (1.0 + 0.5 * std::sin(s)));
  }
  return bc::Waveform::periodic(t, q, period, "verification inflow");
}

} // namespace tearflow::verify
