// Geometric conservation of the ALE fluid (issue 10): a uniform flow through a pipe whose
// mesh moves must stay uniform to solver tolerance. The pipe's inlet has a plug inflow U,
// the outlet and the lateral surface are traction-free, so u = U e_z, p = 0 is the exact
// solution on any domain shape; the mesh then deforms smoothly in time (radial swelling and
// axial stretching, zero at the inlet), which moves the lateral boundary and every interior
// node. The convective ALE form (navier_stokes_kernel.hpp) gives zero residual for it on
// any mesh motion; this test guards that the assembled problem keeps that property (mesh
// velocity, element geometry and outlet normals updated together).
#include <cmath>

#include <gtest/gtest.h>

#include "fem/petsc.hpp"
#include "mesh/orient_faces.hpp"
#include "mesh/pipe_generator.hpp"
#include "physics/fluid_solver.hpp"

using namespace tearflow;

namespace {

constexpr double R = 0.005, L = 0.02, U = 0.3;                  // [m], [m/s]
constexpr double A = 4e-4, omega = 2 * 3.14159265358979 * 20.0; // 0.4 mm at 20 Hz

/// Prescribed mesh displacement: zero at the inlet, growing along the pipe.
Vec3 displacement(const Vec3& X, double t) {
  const double s = A * std::sin(omega * t) * X[2] / L;
  return {s * X[0] / R, s * X[1] / R, 0.5 * s};
}

} // namespace

TEST(Ale, UniformFlowStaysUniformOnAMovingMesh) {
  mesh::Mesh m = mesh::make_pipe({R, L, 0.0015});
  mesh::orient_faces_outward(m);
  fem::DistributedMesh dmesh(m, PETSC_COMM_WORLD);
  const double rho = 1060.0, mu = 0.004;
  bc::FluidConditions conditions;
  double inlet_area = 0.0; // of the polygonal face, so that the plug velocity is exactly U
  for (const Tri& t : m.face("inlet").triangles) {
    const Vec3 c = cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]);
    inlet_area += 0.5 * std::sqrt(dot(c, c));
  }
  const double Q = U * inlet_area;
  conditions.inflows.emplace_back(m, m.face("inlet"), bc::Waveform::constant(Q),
                                  bc::ProfileShape::Plug, rho, mu, 0);
  bc::TractionOutlet outlet;
  outlet.face = "outlet";
  conditions.outlets.push_back(outlet);
  const auto scheme = physics::GeneralizedAlpha::from_spectral_radius(0.5);
  physics::FluidProblem problem(m, dmesh, {rho, mu}, std::move(conditions), scheme);
  physics::FluidSolver solver(problem, {10, 1e-12, 1e-15});

  constexpr int B = physics::FluidProblem::block;
  {
    fem::WriteArray u(solver.solution());
    for (Index l = 0; l < dmesh.num_owned(); ++l)
      u[B * l + 2] = U;
  }
  const double dt = 2e-3;
  const auto n_local = static_cast<size_t>(dmesh.num_local());
  std::vector<Vec3> x(n_local), w(n_local);
  double moved = 0.0;
  for (int step = 0; step < 10; ++step) {
    const double t = step * dt;
    for (Index l = 0; l < dmesh.num_local(); ++l) {
      const Vec3& X = dmesh.points()[l];
      const Vec3 d0 = displacement(X, t), d1 = displacement(X, t + dt);
      x[l] = X + d0 + scheme.alpha_f * (d1 - d0);
      w[l] = (1.0 / dt) * (d1 - d0);
      moved = std::max(moved, std::sqrt(dot(d1, d1)));
    }
    problem.move_mesh(x, w);
    solver.step(t, dt);
  }
  // The mesh moved by up to 0.4 mm (a quarter of an element), with velocities of 0.05 m/s.
  EXPECT_GT(moved, 0.5 * A);
  double du = 0.0, p = 0.0;
  {
    fem::ReadArray u(solver.solution());
    for (Index l = 0; l < dmesh.num_owned(); ++l) {
      du = std::max({du, std::abs(u[B * l]), std::abs(u[B * l + 1]), std::abs(u[B * l + 2] - U)});
      p = std::max(p, std::abs(u[B * l + 3]));
    }
  }
  // Solver tolerance: Newton to 1e-12 relative, GMRES to 1e-4 per iteration: the state
  // stays exact up to round-off (1e-12 of U, of rho U^2).
  EXPECT_LT(du, 1e-10 * U);
  EXPECT_LT(p, 1e-10 * rho * U * U);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  fem::PetscSession petsc(&argc, &argv);
  return RUN_ALL_TESTS();
}
