#include "physics/fsi_problem.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace tearflow::physics {

FsiProblem::FsiProblem(const mesh::Mesh& mesh, const fem::DistributedMesh& dmesh,
                       FluidProperties fluid, bc::FluidConditions fluid_conditions,
                       SolidMaterial wall, bc::SolidConditions wall_conditions,
                       GeneralizedAlpha scheme, FsiRegions regions, bool moving_mesh)
    : dmesh_(dmesh), dofs_(dmesh, block),
      fluid_(mesh, dmesh, fluid, std::move(fluid_conditions), scheme,
             FieldLayout{block, fluid_pressure, regions.fluid}),
      wall_(mesh, dmesh, wall, std::move(wall_conditions), SolidScheme::dynamic(scheme),
            FieldLayout{block, wall_pressure, regions.wall}),
      mesh_(mesh, dmesh, regions.fluid), wall_scheme_(SolidScheme::dynamic(scheme)),
      regions_(regions), moving_mesh_(moving_mesh) {
  // Which physics each node belongs to, from the replicated mesh (a node's tets may sit on
  // other ranks): a pressure slot of a physics without tets at the node is an identity row.
  std::vector<unsigned char> in_fluid(mesh.num_nodes(), 0), in_wall(mesh.num_nodes(), 0);
  for (size_t e = 0; e < mesh.tets.size(); ++e) {
    const int r = mesh.tet_region.empty() ? 0 : mesh.tet_region[e];
    for (Index v : mesh.tets[e])
      (r == regions.fluid ? in_fluid : in_wall)[v] = 1;
  }
  std::vector<unsigned char> wall_node(static_cast<size_t>(dmesh.num_owned()));
  for (Index l = 0; l < dmesh.num_owned(); ++l) {
    const Index n = dmesh.original_index(l);
    if (!in_fluid[n])
      unused_rows_.push_back(dofs_.global_dof(l, fluid_pressure));
    if (!in_wall[n])
      unused_rows_.push_back(dofs_.global_dof(l, wall_pressure));
    wall_node[l] = in_wall[n];
  }
  preconditioner_ =
      std::make_unique<FsiPreconditioner>(dofs_, wall_node, fluid_pressure, wall_pressure);
  identity_rows_ = fluid_.dirichlet_rows();
  const std::vector<PetscInt> wall_rows = wall_.dirichlet_rows();
  identity_rows_.insert(identity_rows_.end(), wall_rows.begin(), wall_rows.end());
  identity_rows_.insert(identity_rows_.end(), unused_rows_.begin(), unused_rows_.end());
  std::sort(identity_rows_.begin(), identity_rows_.end());
  identity_rows_.erase(std::unique(identity_rows_.begin(), identity_rows_.end()),
                       identity_rows_.end());

  // The interface's shape derivatives in the Jacobian (fsi_problem.hpp), unless
  // -fsi_interface_shape_derivatives false.
  PetscBool shape_derivatives = PETSC_TRUE;
  TF_PETSC(PetscOptionsGetBool(nullptr, options_prefix, "-interface_shape_derivatives",
                               &shape_derivatives, nullptr));
  if (moving_mesh_ && shape_derivatives) {
    follows_wall_.resize(static_cast<size_t>(dmesh.num_local()));
    for (Index l = 0; l < dmesh.num_local(); ++l)
      follows_wall_[l] = mesh_.follows_wall(l);
  }

  D_ = dofs_.create_global();
  U_loc_ = dofs_.create_local();
  R_loc_ = dofs_.create_local();
  Un_loc_ = dofs_.create_local();
  An_loc_ = dofs_.create_local();
  Dn_loc_ = dofs_.create_local();
  d_next_.assign(static_cast<size_t>(dmesh.num_local()), Vec3{});
}

fem::OptionList FsiProblem::default_solver_options() {
  // GMRES with the field split of fsi_preconditioner.hpp (the wall's velocity and pressure
  // solved together, the fluid pressure's selfp Schur complement under BoomerAMG), rebuilt
  // every tenth Newton iteration, across steps (pipe-fsi, 2 ranks: 6.5 s/step against 7.4
  // with every third, same Newton counts). A sparse direct solve of the whole system
  // (-fsi_pc_type lu -fsi_pc_factor_mat_solver_type mumps, turtleFSI's choice) needed 1-2
  // iterations but its factorization grew to 14 s per step at 35 k tets (fill of the long
  // tube).
  //
  // Linear solves to 1e-4: with the interface's shape derivatives the Jacobian is Newton's
  // own (the interior mesh held), so an accurate direction is worth its Krylov iterations;
  // to 1e-2 the left-preconditioned solves alternated good and poor Newton steps. Measured,
  // 4.5 mm dissection from its periodic state, dt 5 ms, Newton to 1e-6, 12 steps, 1 rank
  // (Newton / Krylov / CPU s): ksp_rtol 1e-2 82 / 870 / 114, 1e-3 60 / 883 / 107, 1e-4
  // 48 / 930 / 107, 1e-6 44 / 1242 / 130. At the study's 1 mm, where a Newton iteration
  // (residual and Jacobian, about 15 s on 1 rank) costs ten Krylov iterations, 1e-2 took
  // 5-6 Newton and 70-85 Krylov per step, 1e-4 3 and 63 (docs/performance.md, issue 23).
  //
  // Full Newton steps (basic line search): before the shape derivatives, single steps raised
  // ||R|| now and then and backtracking stalled on the same direction (the 4.5 mm dissection
  // at 1.28e-6 in step 1; the 2 mm one failed its line search).
  //
  // Built sooner where a solve takes more than twice the iterations of the first one with the
  // build (preconditioner_lag.hpp): the 4.5 mm dissection's first FSI cycle (dt 20 ms, 2 ranks)
  // 195 -> 172 s, Krylov 1916 -> 1501, the same Newton iterations; its first five steps 71 ->
  // 36 s.
  fem::OptionList options = {{"-fsi_ksp_rtol", "1e-4"},
                             {"-fsi_snes_lag_preconditioner", "10"},
                             {"-fsi_snes_lag_preconditioner_persists", "true"},
                             {"-fsi_lag_preconditioner_growth", "2"}};
  for (auto& option : FsiPreconditioner::default_options())
    options.push_back(std::move(option));
  return options;
}

void FsiProblem::begin_step(double t_n, double dt, Vec U_n, Vec Udot_n) {
  dt_ = dt;
  dofs_.global_to_local(U_n, Un_loc_);
  dofs_.global_to_local(Udot_n, An_loc_);
  dofs_.global_to_local(D_, Dn_loc_);
  // The fluid's lagged stabilization is computed on the configuration at t_n with w = 0,
  // and the mesh motion's first solve starts from d_n: functions of the state alone, so a
  // restarted run repeats the uninterrupted one.
  if (moving_mesh_) {
    place_fluid(Dn_loc_);
    fem::ReadArray d(Dn_loc_);
    std::vector<Vec3> guess(static_cast<size_t>(dmesh_.num_local()));
    for (Index l = 0; l < dmesh_.num_local(); ++l)
      for (int c = 0; c < 3; ++c)
        guess[l][c] = d[block * l + c];
    mesh_.start_from(guess);
  }
  fluid_.begin_step(t_n, dt, U_n, Udot_n);
  wall_.begin_step(t_n, dt, U_n, D_, Udot_n);
  if (!follows_wall_.empty()) // Newmark: d_{n+1} moves by beta dt / gamma per unit of v_{n+1}
    fluid_.set_mesh_sensitivity(
        {follows_wall_, wall_scheme_.c_u(dt), wall_scheme_.beta / wall_scheme_.gamma});
}

void FsiProblem::place_fluid(Vec D_loc) {
  fem::ReadArray d(D_loc);
  const auto& X = dmesh_.points();
  std::vector<Vec3> x(X.size()), w(X.size());
  for (Index l = 0; l < dmesh_.num_local(); ++l)
    for (int c = 0; c < 3; ++c)
      x[l][c] = X[l][c] + d[block * l + c];
  fluid_.move_mesh(x, w);
}

void FsiProblem::apply_dirichlet(Vec U) const {
  fluid_.apply_dirichlet(U);
  wall_.apply_dirichlet(U); // the wall's prescribed motion wins where both prescribe
  fem::WriteArray u(U);
  const PetscInt first = static_cast<PetscInt>(dmesh_.owned_begin()) * block;
  for (PetscInt row : unused_rows_)
    u[row - first] = 0.0;
}

void FsiProblem::move_fluid_mesh(Vec U) {
  dofs_.global_to_local(U, U_loc_);
  const auto [am, af, gamma, beta, quasi_static] = wall_scheme_;
  const auto n_local = static_cast<size_t>(dmesh_.num_local());
  std::vector<Vec3> x(n_local), w(n_local);
  {
    fem::ReadArray v(U_loc_), vn(Un_loc_), an(An_loc_), dn(Dn_loc_);
    for (Index l = 0; l < dmesh_.num_local(); ++l)
      for (int c = 0; c < 3; ++c) { // Newmark, as the wall (solid_problem.cpp)
        const PetscInt i = block * l + c;
        const double a1 = (v[i] - vn[i]) / (gamma * dt_) - (1.0 - gamma) / gamma * an[i];
        d_next_[l][c] = dn[i] + dt_ * vn[i] + dt_ * dt_ * ((0.5 - beta) * an[i] + beta * a1);
      }
    mesh_.solve(d_next_, d_next_);
    check_mesh();
    const auto& X = dmesh_.points();
    for (Index l = 0; l < dmesh_.num_local(); ++l)
      for (int c = 0; c < 3; ++c) {
        const double d_n = dn[block * l + c];
        x[l][c] = X[l][c] + d_n + af * (d_next_[l][c] - d_n);
        w[l][c] = (d_next_[l][c] - d_n) / dt_;
      }
  }
  fluid_.move_mesh(x, w);
}

void FsiProblem::check_mesh() const {
  // The smallest tet volume at X + d_{n+1} relative to its reference volume, and where: the
  // fluid's (mesh motion) and the wall's (a Neo-Hookean wall with J <= 0 has no energy).
  struct {
    double ratio;
    int rank;
  } worst{1.0, 0};
  bool in_wall = false;
  MPI_Comm_rank(dmesh_.comm(), &worst.rank);
  Vec3 where{};
  const auto& X = dmesh_.points();
  const auto& tets = dmesh_.tets();
  for (size_t e = 0; e < tets.size(); ++e) {
    const Tet& t = tets[e];
    const auto x = [&](int k) { return X[t[k]] + d_next_[t[k]]; };
    const double ratio = mesh::signed_volume(x(0), x(1), x(2), x(3)) /
                         mesh::signed_volume(X[t[0]], X[t[1]], X[t[2]], X[t[3]]);
    if (ratio < worst.ratio) {
      worst.ratio = ratio;
      where = 0.25 * (X[t[0]] + X[t[1]] + X[t[2]] + X[t[3]]);
      in_wall = dmesh_.tet_region()[e] != regions_.fluid;
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE_INT, MPI_MINLOC, dmesh_.comm());
  if (worst.ratio > 0.0)
    return;
  std::array<double, 4> info{where[0], where[1], where[2], in_wall ? 1.0 : 0.0};
  MPI_Bcast(info.data(), 4, MPI_DOUBLE, worst.rank, dmesh_.comm());
  throw SolverError(
      fmt::format(
          "the {} mesh inverted: a tet near ({:.4g}, {:.4g}, {:.4g}) m (reference position) has "
          "volume {:.3g} times its reference volume at the end of the step; the wall moved too far "
          "in one step (reduce the time step or the load, or check the wall's material and "
          "supports)",
          info[3] > 0.5 ? "wall" : "moving fluid", info[0], info[1], info[2], worst.ratio),
      true);
}

void FsiProblem::residual(Vec U, Vec R) {
  if (moving_mesh_)
    move_fluid_mesh(U);
  TF_PETSC(VecZeroEntries(R_loc_));
  fluid_.add_residual(U, R_loc_);
  wall_.add_residual(U, R_loc_);
  TF_PETSC(VecZeroEntries(R));
  dofs_.add_local_to_global(R_loc_, R);
  fluid_.set_dirichlet_residual(U, R);
  wall_.set_dirichlet_residual(U, R);
  fem::WriteArray r(R);
  fem::ReadArray u(U);
  const PetscInt first = static_cast<PetscInt>(dmesh_.owned_begin()) * block;
  for (PetscInt row : unused_rows_)
    r[row - first] = u[row - first];
}

void FsiProblem::jacobian(Vec U, Mat J) {
  fluid_.add_jacobian(U, J);       // zeroes J first
  wall_.add_jacobian(U, J, false); // its Dirichlet rows are among identity_rows_
  // The identity rows' diagonal entries must exist (a wall node's fluid-pressure slot gets
  // no element entry), or the first assembly drops them from the pattern.
  for (PetscInt row : identity_rows_)
    TF_PETSC(MatSetValue(J, row, row, 0.0, ADD_VALUES));
  TF_PETSC(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
  TF_PETSC(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  TF_PETSC(MatSetOption(J, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE));
  TF_PETSC(MatZeroRows(J, static_cast<PetscInt>(identity_rows_.size()), identity_rows_.data(), 1.0,
                       nullptr, nullptr));
}

void FsiProblem::update_acceleration(Vec U_next, Vec /*U_n*/, Vec Udot) {
  wall_.update_state(U_next, D_, Udot); // Newmark displacement and acceleration, every node
  if (!moving_mesh_)
    return;
  move_fluid_mesh(U_next); // d_{n+1} inside the fluid from the converged wall
  fem::WriteArray d(D_);
  for (Index l = 0; l < dmesh_.num_owned(); ++l)
    for (int c = 0; c < 3; ++c)
      d[block * l + c] = d_next_[l][c];
}

void FsiProblem::set_displacement(const std::vector<double>& all) {
  {
    fem::WriteArray d(D_);
    for (Index l = 0; l < dmesh_.num_owned(); ++l)
      for (int c = 0; c < block; ++c)
        d[block * l + c] = all[block * dmesh_.original_index(l) + c];
  }
  if (!moving_mesh_)
    return;
  dofs_.global_to_local(D_, Dn_loc_);
  place_fluid(Dn_loc_);
}

void FsiProblem::set_wall_displacement(const std::vector<double>& all) {
  std::vector<Vec3> d(static_cast<size_t>(dmesh_.num_local()));
  for (Index l = 0; l < dmesh_.num_local(); ++l)
    for (int c = 0; c < 3; ++c)
      d[l][c] = all[block * dmesh_.original_index(l) + c];
  mesh_.solve(d, d); // the fluid's nodes follow the wall's
  {
    fem::WriteArray D(D_);
    for (Index l = 0; l < dmesh_.num_owned(); ++l)
      for (int c = 0; c < 3; ++c)
        D[block * l + c] = d[l][c];
  }
  dofs_.global_to_local(D_, Dn_loc_);
  place_fluid(Dn_loc_);
}

double FsiProblem::fluid_volume() const {
  fem::OwnedVec D_loc = dofs_.create_local();
  dofs_.global_to_local(D_, D_loc);
  fem::ReadArray d(D_loc);
  const auto& X = dmesh_.points();
  auto x = [&](Index l) {
    return Vec3{X[l][0] + d[block * l], X[l][1] + d[block * l + 1], X[l][2] + d[block * l + 2]};
  };
  double volume = 0.0;
  const auto& tets = dmesh_.tets();
  for (size_t e = 0; e < tets.size(); ++e)
    if (dmesh_.tet_region()[e] == regions_.fluid) {
      const Tet& t = tets[e];
      volume += mesh::signed_volume(x(t[0]), x(t[1]), x(t[2]), x(t[3]));
    }
  MPI_Allreduce(MPI_IN_PLACE, &volume, 1, MPI_DOUBLE, MPI_SUM, dmesh_.comm());
  return volume;
}

double FsiProblem::wall_stiffness_number(double dt) const {
  const auto& X = dmesh_.points();
  const auto& tets = dmesh_.tets();
  const double edge_per_volume = 6.0 * std::sqrt(2.0); // regular tet: V = a^3 / (6 sqrt 2)
  std::array<double, 2> sum{0.0, 0.0};                 // sum of h^2, count
  for (size_t e = 0; e < tets.size(); ++e)
    if (dmesh_.tet_region()[e] == regions_.wall) { // each tet on one rank
      const Tet& t = tets[e];
      const double v = std::abs(mesh::signed_volume(X[t[0]], X[t[1]], X[t[2]], X[t[3]]));
      const double h = std::cbrt(edge_per_volume * v);
      sum[0] += h * h;
      sum[1] += 1.0;
    }
  MPI_Allreduce(MPI_IN_PLACE, sum.data(), 2, MPI_DOUBLE, MPI_SUM, dmesh_.comm());
  if (sum[1] == 0.0)
    return 0.0;
  const SolidMaterial& m = wall_.material();
  return m.youngs_modulus() / m.density * dt * dt * sum[1] / sum[0];
}

double FsiProblem::select_solver(double dt) const {
  const double lambda = wall_stiffness_number(dt);
  fem::set_default_options(FsiPreconditioner::wall_options(lambda));
  // Newton keeps its Jacobian where the last iteration contracted ||R|| a hundredfold
  // (fluid_solver.cpp) when the wall's inertia dominates the step (small Lambda: the step is
  // nearly linear and the Jacobian barely moves within it), not when its elasticity does.
  // pipe-fsi (Lambda 8.1, contractions 3e-3): one Jacobian per step instead of three, 3.5 ->
  // 2.7 s/step on 2 ranks, Newton unchanged; the large-step tube (Lambda 56): 5, 5, 5
  // iterations as with one every iteration, 4 Jacobians each instead of 5 (with a threshold of
  // 0.1 the kept Jacobian's linear rate, 0.2-0.1, needed more than its 7). The 1 mm dissection
  // at dt 5 ms (Lambda 1.6e4): Newton 3.5 -> 4.0 and Krylov 120 -> 160 per step at peak
  // systole, 103 -> 122 s/step, where a Jacobian costs a tenth of an iteration's linear solve.
  fem::set_default_options({{"-fsi_jacobian_reuse_contraction",
                             FsiPreconditioner::wall_solved_directly(lambda) ? "0" : "0.01"}});
  return lambda;
}

} // namespace tearflow::physics
