// Flow split at a three-outlet junction closed by RCR Windkessels. The outlets' resistances
// are distributed as in the reference study (../shared/reference/tbad-study.md):
// R_i = R_T / f_i, R_p = (1 - k_d) R_i, R_d = k_d R_i, C_i = C_T f_i, so that the 0D model
// of the outlets (bc/windkessel_network.hpp: the inflow into parallel RCRs) splits the mean
// flow as f_i. The 3D run adds the junction's own resistance, small against the outlets'.
// Starting from the 0D periodic state, its first cycle is compared with the 0D prediction.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bc/windkessel_network.hpp"
#include "core/units.hpp"
#include "mesh/junction_generator.hpp"
#include "run/simulation.hpp"
#include "verify/cases.hpp"
#include "verify/pulsatile_inflow.hpp"

namespace tearflow::verify {

namespace {

constexpr double rho = 1060.0, mu = 0.004;
constexpr double T = 1.0, dt = 0.01;
constexpr double Q_mean = 1e-5;                          // [m^3/s]; peak Re ~ 800 in the trunk
constexpr double R_T = 1.5e8, C_T = 6.74e-9, k_d = 0.84; // the study's OR model
constexpr std::array<double, 3> kSplit = {0.5, 0.3, 0.2};
const std::array<const char*, 3> kOutlets = {"outlet_1", "outlet_2", "outlet_3"};

bc::WindkesselRCR outlet_rcr(double f) {
  const double r = R_T / f;
  return {(1.0 - k_d) * r, C_T * f, k_d * r, 0.0};
}

io::Case splits_case(double element_size) {
  io::Case c;
  c.name = "verify-splits";
  mesh::JunctionSpec spec;
  spec.element_size = element_size;
  c.mesh.generator = [spec](const io::Case&) { return mesh::make_junction(spec); };
  c.fluid = {rho, mu};
  c.time.step = dt;
  c.time.period = T;
  c.time.steps_per_cycle = static_cast<int>(std::round(T / dt));
  c.time.steps = c.time.steps_per_cycle;
  c.boundary_conditions = {{"wall", bc::NoSlip{}},
                           {"inlet", bc::Inflow{pulsatile_inflow(Q_mean, T)}}};
  for (size_t i = 0; i < kOutlets.size(); ++i)
    c.boundary_conditions.push_back(
        {kOutlets[i], bc::Outlet{bc::RcrOutlet{outlet_rcr(kSplit[i]), {}}}});
  c.newton = {10, 1e-6, 1e-14};
  return c;
}

} // namespace

VerificationResult verify_splits(const VerifyOptions& options) {
  const double h = 0.0012 * options.coarsening;
  io::Case config = splits_case(h);
  run::Simulation sim(config);
  run::RunRecord record({kOutlets.begin(), kOutlets.end()}, sim.config().time.steps_per_cycle, T);
  record.add(sim.sample());
  std::optional<run::CycleStats> cycle;
  int newton = 0;
  for (int s = 0; s < sim.config().time.steps; ++s) {
    const physics::StepReport r = sim.advance();
    newton += r.newton_iterations;
    if (options.progress)
      fmt::print(stderr, "splits: step {}/{} Newton {} KSP {}\n", s + 1, sim.config().time.steps,
                 r.newton_iterations, r.linear_iterations);
    cycle = record.add(sim.sample());
  }

  std::vector<bc::WindkesselBranch> branches;
  for (size_t i = 0; i < kOutlets.size(); ++i)
    branches.push_back({kOutlets[i], outlet_rcr(kSplit[i])});
  const bc::PeriodicState zero_d =
      bc::WindkesselNetwork(branches).periodic(config.boundary_conditions[1].inflow()->flow);
  double total = 0.0;
  for (size_t i = 0; i < kOutlets.size(); ++i)
    total += zero_d.mean_branch_flow(i);

  VerificationResult res;
  res.name = "splits";
  // A run that completed no cycle, or an outlet missing from it, leaves a NaN: it fails.
  const int outlets_measured =
      cycle ? static_cast<int>(std::count_if(
                  cycle->faces.begin(), cycle->faces.end(),
                  [](const run::FaceCycleStats& f) { return f.split_percent.has_value(); }))
            : 0;
  res.metrics.push_back({"outlet_count_error",
                         std::abs(static_cast<double>(kOutlets.size()) - outlets_measured), 0.0,
                         "|outlets - outlets with a measured split in the cycle|; 0"});
  double worst = cycle ? 0.0 : NAN;
  nlohmann::json table = nlohmann::json::array();
  for (size_t i = 0; i < kOutlets.size(); ++i) {
    const double predicted = 100.0 * zero_d.mean_branch_flow(i) / total;
    double measured = NAN;
    if (cycle)
      for (const run::FaceCycleStats& f : cycle->faces)
        if (f.face == kOutlets[i])
          measured = f.split_percent.value_or(NAN);
    worst = worst_of(worst, std::abs(measured - predicted));
    table.push_back(
        {{"outlet", kOutlets[i]}, {"split_3d_percent", measured}, {"split_0d_percent", predicted}});
  }
  // The junction and branches add ~2e6 Pa s/m^3 of viscous resistance in series with
  // outlets of 3e8-7.5e8 (< 1 % of each), and the cycle's volumes carry the trapezoidal
  // rule's O(dt^2) error: 2 percentage points (the bound) is a wide margin.
  res.metrics.push_back({"split_error_percent_points", worst, 2.0,
                         "max over outlets of |3D split - 0D split| over one cycle, in % points"});
  res.details = {
      {"element_size_m", h},
      {"tets", sim.mesh().num_tets()},
      {"time_step_s", dt},
      {"newton_iterations_per_step", static_cast<double>(newton) / sim.config().time.steps},
      {"R_T", R_T},
      {"C_T", C_T},
      {"k_d", k_d},
      {"splits", table},
      {"cycle", cycle ? run::cycles_to_json(T, {*cycle}) : nlohmann::json()}};
  return res;
}

} // namespace tearflow::verify
