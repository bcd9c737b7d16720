#include "run/default_case.hpp"

#include <filesystem>

namespace tearflow::run {

io::Case default_case() {
  io::Case c;
  c.name = "pulsatile-pipe";
  c.mesh.pipe = mesh::PipeSpec{0.01, 0.1, 0.0015};
  c.fluid = {1060.0, 0.004};
  // Two cardiac cycles of 100 steps; the outlet starts from its periodic 0D state.
  c.time.step = 0.01;
  c.time.spectral_radius = 0.5;
  c.time.period = 1.0;
  c.time.steps_per_cycle = 100;
  c.time.steps = 200;
  // An aortic-like waveform [mL/s] over a 1 s cycle: systolic peak at 0.15 s, small
  // reversal in early diastole; mean about 21 mL/s (scaled down for a 2 cm pipe).
  const std::vector<double> t{0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.5, 0.6, 0.8};
  const std::vector<double> q{2.0, 30.0, 75.0, 90.0, 70.0, 40.0, 12.0, -6.0, 0.0, 4.0, 3.0, 2.0};
  std::vector<double> q_si;
  for (double v : q)
    q_si.push_back(v * 1e-6);
  io::BoundaryCondition wall, inlet, outlet;
  wall.face = "wall";
  inlet.face = "inlet";
  inlet.type = io::BcType::Inflow;
  inlet.flow = bc::Waveform::periodic(t, q_si, 1.0, "built-in waveform");
  // The reference study's OR Windkessel totals (../shared/reference/tbad-study.md):
  // R_T = 150 MPa s/m^3, C_T = 6.74e-9 m^3/Pa, k_d = 0.84, on the single outlet.
  outlet.face = "outlet";
  outlet.type = io::BcType::Windkessel;
  outlet.rcr = {0.16 * 1.5e8, 6.74e-9, 0.84 * 1.5e8, 0.0};
  c.boundary_conditions = {wall, inlet, outlet};
  c.newton = {10, 1e-6, 1e-12};
  c.output.directory = std::filesystem::absolute("results/pulsatile-pipe");
  c.output.every = 10;
  c.output.checkpoint_every = 50;
  return c;
}

} // namespace tearflow::run
