// Geometric conservation of the ALE fluid (issue 10): a uniform flow through a pipe whose
// mesh moves must stay uniform to solver tolerance. The pipe's inlet has a plug inflow U,
// the outlet and the lateral surface are traction-free, so u = U e_z, p = 0 is the exact
// solution on any domain shape; the mesh then deforms smoothly in time (radial swelling and
// axial stretching, zero at the inlet), which moves the lateral boundary and every interior
// node. The convective ALE form (navier_stokes_kernel.hpp) gives zero residual for it on
// any mesh motion; this test guards that the assembled problem keeps that property (mesh
// velocity, element geometry and outlet normals updated together).
//
// A uniform flow has no gradient, so it cannot tell whether the mesh velocity enters the
// convective term at all. The second test does: an inviscid shear flow
//   u = (0, 0, U + G x),  p = 0,
// is an exact steady solution (div u = 0, u . grad u = u_x G = 0, no viscous stress) on any
// domain with traction-free faces, and P1 represents it exactly. The mesh deforms with a
// velocity w(X) that is constant in time but not in space, so the nodal values change,
// du_z/dt|_X = G w_x, and the ALE residual rho (du/dt|_X + (u - w) . grad u) vanishes only
// if the mesh velocity cancels that change term by term. Leaving w out, or the wrong sign,
// or the geometry one configuration behind, gives a residual rho G w_x = O(1e3 Pa/m) and a
// velocity error of G w_x dt per step (3e-3 of U here), far above the checked 1e-9.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

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
  conditions.outlets.push_back({"outlet", bc::PressureOutlet{}}); // traction-free
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

namespace {

constexpr double G = 20.0, V = 0.05; // shear rate [1/s]; mesh speed scale [m/s]

/// The mesh velocity: swelling and stretching that vanish at the inlet, plus a sideways
/// shear, so that w_x differs from node to node (constant in time).
Vec3 mesh_velocity(const Vec3& X) {
  const double s = V * X[2] / L;
  return {s * X[0] / R + 0.5 * V * X[1] / R, s * X[1] / R, 0.5 * s};
}

} // namespace

TEST(Ale, ShearFlowFollowsTheMeshVelocityTerms) {
  mesh::Mesh m = mesh::make_pipe({R, L, 0.0015});
  mesh::orient_faces_outward(m);
  fem::DistributedMesh dmesh(m, PETSC_COMM_WORLD);
  const double rho = 1060.0;
  bc::FluidConditions conditions; // every face traction-free: the exact solution has p = 0
  const auto scheme = physics::GeneralizedAlpha::from_spectral_radius(0.5);
  physics::FluidProblem problem(m, dmesh, {rho, 0.0}, std::move(conditions), scheme);
  physics::FluidSolver solver(problem, {10, 1e-12, 1e-15});

  constexpr int B = physics::FluidProblem::block;
  const auto n_local = static_cast<size_t>(dmesh.num_local());
  std::vector<Vec3> x(n_local), w(n_local);
  for (Index l = 0; l < dmesh.num_local(); ++l)
    w[l] = mesh_velocity(dmesh.points()[l]);
  { // The exact state at t = 0: u on the reference nodes, du/dt|_X = G w_x e_z.
    fem::WriteArray u(solver.solution()), a(solver.acceleration());
    for (Index l = 0; l < dmesh.num_owned(); ++l) {
      u[B * l + 2] = U + G * dmesh.points()[l][0];
      a[B * l + 2] = G * w[l][0];
    }
  }
  const double dt = 1e-3;
  const int steps = 10;
  for (int step = 0; step < steps; ++step) {
    const double t = step * dt;
    for (Index l = 0; l < dmesh.num_local(); ++l)
      x[l] = dmesh.points()[l] + (t + scheme.alpha_f * dt) * w[l];
    problem.move_mesh(x, w);
    solver.step(t, dt);
  }
  double w_min = 0.0, w_max = 0.0, du = 0.0, p = 0.0;
  {
    fem::ReadArray u(solver.solution());
    for (Index l = 0; l < dmesh.num_owned(); ++l) {
      const double x_now = dmesh.points()[l][0] + steps * dt * w[l][0];
      du = std::max({du, std::abs(u[B * l]), std::abs(u[B * l + 1]),
                     std::abs(u[B * l + 2] - (U + G * x_now))});
      p = std::max(p, std::abs(u[B * l + 3]));
      w_min = std::min(w_min, w[l][0]);
      w_max = std::max(w_max, w[l][0]);
    }
  }
  const double spread = w_max - w_min; // of w_x between the nodes [m/s]
  // The test means something only if the nodal values had to change: the shear across the
  // moved nodes changed u_z by G (w_x spread) t, about 7 % of U over the run.
  EXPECT_GT(G * spread * steps * dt, 1e-4 * U);
  // Solver tolerance: Newton to 1e-12 relative (1e-15 absolute) on an exact discrete
  // solution: round-off of U and of rho U^2.
  EXPECT_LT(du, 1e-9 * U);
  EXPECT_LT(p, 1e-9 * rho * U * U);
}

// The FSI Jacobian's interface part (fsi_problem.hpp): nodes that move with their own velocity
// unknown (x by dx_du, w by dw_du per unit of u) add the element residual's dependence on that
// motion. Checked against central differences of the assembled residual, the mesh moved by
// the same rule, in a random direction: the element-wise forward differences are accurate to
// ~1e-7 relative (their step is 1e-7 of an element), the central ones of the whole residual to
// O(h^2), so the two must agree to 1e-5; without the motion term they differ by the term's
// whole size, which must be far larger (at least 1e-2 here) for the check to mean anything.
TEST(Ale, JacobianHoldsTheMotionOfFollowingNodes) {
  mesh::Mesh m = mesh::make_pipe({R, L, 0.0015});
  mesh::orient_faces_outward(m);
  fem::DistributedMesh dmesh(m, PETSC_COMM_WORLD);
  const double rho = 1060.0, mu = 0.004, dt = 5e-3;
  bc::FluidConditions conditions; // traction-free faces: every dof is free
  const auto scheme = physics::GeneralizedAlpha::from_spectral_radius(0.5);
  physics::FluidProblem problem(m, dmesh, {rho, mu}, std::move(conditions), scheme);
  const fem::DofMap& dofs = problem.dofs();
  constexpr int B = physics::FluidProblem::block;

  // The lateral wall's nodes follow, as an FSI interface's do (the Newmark factors of
  // spectral radius 0.5: dx/du = alpha_f beta dt / gamma, dw/du = beta / gamma).
  std::vector<std::uint8_t> follows(static_cast<size_t>(dmesh.num_local()), 0);
  for (Index l = 0; l < dmesh.num_local(); ++l) {
    const Vec3& X = dmesh.points()[l];
    follows[l] = std::hypot(X[0], X[1]) > 0.99 * R;
  }
  const double beta = 0.25 * std::pow(1.0 + scheme.alpha_m - scheme.alpha_f, 2);
  const double dx_du = scheme.alpha_f * beta * dt / scheme.gamma, dw_du = beta / scheme.gamma;

  // A state with gradients everywhere: shear, swirl and a pressure field; the mesh moving.
  fem::OwnedVec state = dofs.create_global(), Un = dofs.create_global(), An = dofs.create_global();
  {
    fem::WriteArray u(state), un(Un);
    for (Index l = 0; l < dmesh.num_owned(); ++l) {
      const Vec3& X = dmesh.points()[l];
      const double z = X[2] / L;
      const double v[4] = {-300.0 * X[1] + 0.02 * z, 300.0 * X[0], U + G * X[0] + 0.1 * z * z,
                           2000.0 * (1.0 - z) + 5e4 * X[0] * X[1]};
      for (int c = 0; c < 4; ++c) {
        u[B * l + c] = v[c];
        un[B * l + c] = 0.9 * v[c];
      }
    }
  }
  std::vector<Vec3> x0(static_cast<size_t>(dmesh.num_local())), w0(x0.size());
  for (Index l = 0; l < dmesh.num_local(); ++l) {
    w0[l] = mesh_velocity(dmesh.points()[l]);
    x0[l] = dmesh.points()[l] + (scheme.alpha_f * dt) * w0[l];
  }
  problem.move_mesh(x0, w0);
  problem.begin_step(0.0, dt, Un, An);

  // A random direction v, its local values (the ghosts' too) for the mesh's motion.
  fem::OwnedVec v = dofs.create_global(), v_loc = dofs.create_local();
  {
    fem::WriteArray a(v);
    unsigned seed = 28;
    for (PetscInt i = 0; i < dofs.num_owned_dofs(); ++i) {
      seed = seed * 1103515245u + 12345u;
      a[i] = (static_cast<double>(seed >> 8 & 0xffff) / 65535.0 - 0.5) * (i % B == 3 ? 1e3 : 1.0);
    }
  }
  dofs.global_to_local(v, v_loc);

  auto residual_moved = [&](double h, Vec R) {
    fem::OwnedVec Uh = dofs.create_global();
    TF_PETSC(VecWAXPY(Uh, h, v, state));
    std::vector<Vec3> x = x0, w = w0;
    fem::ReadArray a(v_loc);
    for (Index l = 0; l < dmesh.num_local(); ++l)
      if (follows[l])
        for (int c = 0; c < 3; ++c) {
          x[l][c] += dx_du * h * a[B * l + c];
          w[l][c] += dw_du * h * a[B * l + c];
        }
    problem.move_mesh(x, w);
    problem.residual(Uh, R);
  };
  const double h = 1e-6;
  fem::OwnedVec Rp = dofs.create_global(), Rm = dofs.create_global();
  residual_moved(h, Rp);
  residual_moved(-h, Rm);
  TF_PETSC(VecAXPY(Rp, -1.0, Rm));
  TF_PETSC(VecScale(Rp, 0.5 / h)); // the directional derivative, motion included
  PetscReal fd = 0.0;
  TF_PETSC(VecNorm(Rp, NORM_2, &fd));

  auto mismatch = [&](bool with_motion) {
    problem.move_mesh(x0, w0);
    problem.set_mesh_sensitivity(with_motion
                                     ? physics::FluidProblem::MeshSensitivity{follows, dx_du, dw_du}
                                     : physics::FluidProblem::MeshSensitivity{});
    fem::OwnedMat J = dofs.create_matrix("ale_test_");
    problem.jacobian(state, J);
    fem::OwnedVec Jv = dofs.create_global();
    TF_PETSC(MatMult(J, v, Jv));
    TF_PETSC(VecAXPY(Jv, -1.0, Rp));
    PetscReal e = 0.0;
    TF_PETSC(VecNorm(Jv, NORM_2, &e));
    return e / fd;
  };
  const double with = mismatch(true), without = mismatch(false);
  std::printf("|J v - FD| / |FD|: %.2e with the motion term, %.2e without\n", with, without);
  EXPECT_LT(with, 1e-5);
  EXPECT_GT(without, 1e-2);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  fem::PetscSession petsc(&argc, &argv);
  return RUN_ALL_TESTS();
}
