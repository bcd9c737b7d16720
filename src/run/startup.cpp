#include "run/startup.hpp"

#include <algorithm>

namespace tearflow::run {

bc::Waveform total_inflow(const bc::FluidConditions& conditions) {
  const auto& inflows = conditions.inflows;
  if (inflows.size() == 1)
    return inflows[0].flow();
  double period = 0.0, constant = 0.0;
  for (const bc::InflowProfile& p : inflows) {
    period = std::max(period, p.flow().period());
    constant += p.flow()(0.0);
  }
  if (period == 0.0)
    return bc::Waveform::constant(constant);
  // Several periodic inflows share the case's period (checked on load): sample their sum
  // finely enough that the spline through it is the sum to well below 0.1 %.
  constexpr int samples = 1000;
  std::vector<double> t(samples), v(samples, 0.0);
  for (int k = 0; k < samples; ++k) {
    t[k] = period * k / samples;
    for (const bc::InflowProfile& p : inflows)
      v[k] += p.flow()(t[k]);
  }
  return bc::Waveform::periodic(t, v, period, "the sum of the inflows");
}

std::optional<OutletModel> outlet_model(const bc::FluidConditions& conditions) {
  if (conditions.inflows.empty())
    return std::nullopt;
  std::vector<bc::WindkesselBranch> branches;
  std::vector<size_t> index;
  bool any_capacitor = false;
  for (size_t i = 0; i < conditions.outlets.size(); ++i) {
    const bc::TractionOutlet& o = conditions.outlets[i];
    const std::optional<bc::WindkesselRCR> branch = bc::zero_d_branch(o.law);
    if (!branch)
      return std::nullopt; // an outlet that sets the pressure: nothing to start
    branches.push_back({o.face, *branch});
    any_capacitor = any_capacitor || branches.back().has_capacitor();
    index.push_back(i);
  }
  if (!any_capacitor)
    return std::nullopt;
  return OutletModel{bc::WindkesselNetwork(std::move(branches)), total_inflow(conditions), index};
}

} // namespace tearflow::run
