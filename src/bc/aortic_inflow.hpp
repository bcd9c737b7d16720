#pragma once
// A typical aortic inflow for when no measured waveform is at hand: ejection as a half sine
// of peak Q_peak during systole, no flow in diastole. The systole lasts
// T_s = pi SV / (2 Q_peak) so that the stroke volume is SV; the reference study's inflow
// (SV 74.1 mL, peak 300 mL/s, period 1 s; ../shared/reference/tbad-study.md) gives
// T_s = 0.388 s and a mean of 4.45 L/min.
#include <cmath>
#include <numbers>
#include <vector>

#include "bc/waveform.hpp"
#include "core/error.hpp"

namespace tearflow::bc {

inline Waveform typical_aortic_inflow(double stroke_volume, double peak_flow, double period) {
  const double systole = std::numbers::pi * stroke_volume / (2.0 * peak_flow);
  if (!(stroke_volume > 0.0 && peak_flow > 0.0 && systole < period))
    input_error("aortic inflow: stroke volume {} m^3 at peak {} m^3/s does not fit in a {} s "
                "cycle",
                stroke_volume, peak_flow, period);
  // Samples every 5 ms through systole and every 20 ms through diastole keep the spline's
  // overshoot at the end of systole below 1 % of the peak.
  std::vector<double> t, q;
  for (double s = 0.0; s < systole; s += 0.005) {
    t.push_back(s);
    q.push_back(peak_flow * std::sin(std::numbers::pi * s / systole));
  }
  for (double s = systole; s < period - 1e-9; s += 0.02) {
    t.push_back(s);
    q.push_back(0.0);
  }
  return Waveform::periodic(t, q, period, "typical aortic inflow");
}

} // namespace tearflow::bc
