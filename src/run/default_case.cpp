// The built-in default case: rigid-wall flow in the parametric type B aortic dissection
// (geometry/tbad_*, OR variant, 3 mm elements) with the reference study's inflow and
// Windkessel outlets (../shared/reference/tbad-study.md).
#include "run/default_case.hpp"

#include "core/file_layout.hpp"

#include <filesystem>

#include <mpi.h>

#include "bc/aortic_inflow.hpp"
#include "fem/petsc.hpp"
#include "geometry/tbad_builder.hpp"
#include "mesh/readers.hpp"

namespace tearflow::run {

namespace {

/// RCRs from the study's OR totals distributed by its measured flow splits:
/// R_i = R_T / f_i, R_p = (1 - k_d) R_i, R_d = k_d R_i, C_i = C_T f_i.
bc::BoundaryCondition study_outlet(const std::string& face, double split_percent) {
  constexpr double R_T = 150e6, C_T = 6.74e-9, k_d = 0.84, total_percent = 100.0;
  const double f = split_percent / total_percent, R = R_T / f;
  return {face, bc::Outlet{bc::RcrOutlet{{(1.0 - k_d) * R, C_T * f, k_d * R, 0.0}, {}}}};
}

} // namespace

io::Case default_case() {
  io::Case c;
  c.name = "tbad-or";
  c.output.directory = std::filesystem::absolute("results/tbad-or");
  // Rank 0 builds and writes the model beside the results; every rank then reads the same
  // file, so that all hold the same mesh.
  c.mesh.generator = [](const io::Case& self) {
    const GeometryFiles geometry = RunFiles{self.output.directory}.geometry();
    if (fem::mpi_rank() == 0)
      geometry::build_tbad(geometry::TbadSpec{}, geometry.dir);
    MPI_Barrier(PETSC_COMM_WORLD);
    return mesh::read_mesh(geometry.mesh(), 1e-3);
  };
  c.mesh.region = "fluid";
  c.fluid = {1100.0, 0.0042}; // the study's blood-mimicking fluid
  // Two cardiac cycles of 200 steps; the outlets start from their periodic 0D state.
  c.time.step = 0.005;
  c.time.spectral_radius = 0.5;
  c.time.period = 1.0;
  c.time.steps_per_cycle = 200;
  c.time.steps = 400;
  const bc::Inflow inflow{bc::typical_aortic_inflow(74.1e-6, 300e-6, 1.0)}; // SV 74.1 mL,
                                                                            // peak 300 mL/s
  // Measured flow splits, % of outflow (they sum to 100).
  c.boundary_conditions = {{"interface", bc::NoSlip{}}, {"inlet", inflow},
                           study_outlet("BCT", 15.0),   study_outlet("LCC", 3.1),
                           study_outlet("LSA", 5.4),    study_outlet("outlet", 76.5)};
  c.newton = {10, 1e-6, 1e-12};
  c.output.every = 10;
  c.output.checkpoint_every = 50;
  return c;
}

} // namespace tearflow::run
