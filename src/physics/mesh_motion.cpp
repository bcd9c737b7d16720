#include "physics/mesh_motion.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"
#include "fem/p1_tet.hpp"

namespace tearflow::physics {

namespace {

/// Per node of the replicated mesh: a node of a wall (non-fluid) tet, a node on the fluid's
/// boundary elsewhere (faces of one fluid tet only), or a free interior node.
std::vector<unsigned char> node_roles(const mesh::Mesh& mesh, int fluid_region) {
  enum : unsigned char { Free = 0, Wall = 1, Fixed = 2 };
  std::vector<unsigned char> role(mesh.num_nodes(), Free);
  std::vector<std::array<Index, 3>> faces;
  for (size_t e = 0; e < mesh.tets.size(); ++e) {
    const Tet& t = mesh.tets[e];
    if (!mesh.tet_region.empty() && mesh.tet_region[e] != fluid_region) {
      for (Index v : t)
        role[v] = Wall;
      continue;
    }
    for (int skip = 0; skip < 4; ++skip) {
      std::array<Index, 3> f{};
      for (int a = 0, k = 0; a < 4; ++a)
        if (a != skip)
          f[k++] = t[a];
      std::sort(f.begin(), f.end());
      faces.push_back(f);
    }
  }
  std::sort(faces.begin(), faces.end());
  for (size_t i = 0; i < faces.size();) {
    size_t j = i;
    while (j < faces.size() && faces[j] == faces[i])
      ++j;
    if (j - i == 1) // a boundary face of the fluid
      for (Index v : faces[i])
        if (role[v] != Wall)
          role[v] = Fixed;
    i = j;
  }
  return role;
}

} // namespace

MeshMotion::MeshMotion(const mesh::Mesh& mesh, const fem::DistributedMesh& dmesh, int fluid_region)
    : dmesh_(dmesh), dofs_(dmesh, 3) {
  const std::vector<unsigned char> global_role = node_roles(mesh, fluid_region);
  role_.resize(static_cast<size_t>(dmesh.num_local()));
  for (Index l = 0; l < dmesh.num_local(); ++l)
    role_[l] = static_cast<Role>(global_role[dmesh.original_index(l)]);
  for (Index l = 0; l < dmesh.num_owned(); ++l)
    if (role_[l] != Role::Free)
      for (int c = 0; c < 3; ++c)
        constrained_rows_.push_back(dofs_.global_dof(l, c));

  // Mean fluid tet volume, for the stiffening.
  const auto& tets = dmesh.tets();
  const auto& x = dmesh.points();
  std::vector<size_t> fluid;
  double sums[2] = {0.0, 0.0};
  for (size_t e = 0; e < tets.size(); ++e)
    if (dmesh.tet_region()[e] == fluid_region) {
      fluid.push_back(e);
      const Tet& t = tets[e];
      sums[0] += fem::tet_geometry({x[t[0]], x[t[1]], x[t[2]], x[t[3]]}).volume;
      sums[1] += 1.0;
    }
  MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, dmesh.comm());
  const double v_mean = sums[1] > 0.0 ? sums[0] / sums[1] : 1.0;

  A0_ = dofs_.create_matrix("mesh_");
  constexpr double mu = 1.0, lambda = 1.0;
  std::array<double, 144> K;
  std::array<PetscInt, 12> dofs;
  for (size_t e : fluid) {
    const Tet& t = tets[e];
    const fem::TetGeometry g = fem::tet_geometry({x[t[0]], x[t[1]], x[t[2]], x[t[3]]});
    const double s = v_mean; // s_e V_e with s_e = V_mean / V_e (chi = 1)
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i) {
        dofs[3 * a + i] = dofs_.global_dof(t[a], i);
        for (int b = 0; b < 4; ++b)
          for (int j = 0; j < 3; ++j)
            K[(3 * a + i) * 12 + 3 * b + j] =
                s *
                (mu * ((i == j ? dot(g.grad[a], g.grad[b]) : 0.0) + g.grad[a][j] * g.grad[b][i]) +
                 lambda * g.grad[a][i] * g.grad[b][j]);
      }
    TF_PETSC(MatSetValues(A0_, 12, dofs.data(), 12, dofs.data(), K.data(), ADD_VALUES));
  }
  // Every diagonal entry exists (the wall's nodes have no fluid tet), so that the
  // constrained rows can become identity rows.
  for (Index l = 0; l < dmesh.num_owned(); ++l)
    for (int c = 0; c < 3; ++c)
      TF_PETSC(MatSetValue(A0_, dofs_.global_dof(l, c), dofs_.global_dof(l, c), 0.0, ADD_VALUES));
  TF_PETSC(MatAssemblyBegin(A0_, MAT_FINAL_ASSEMBLY));
  TF_PETSC(MatAssemblyEnd(A0_, MAT_FINAL_ASSEMBLY));
  TF_PETSC(MatDuplicate(A0_, MAT_COPY_VALUES, A_.out()));
  TF_PETSC(MatZeroRowsColumns(A_, static_cast<PetscInt>(constrained_rows_.size()),
                              constrained_rows_.data(), 1.0, nullptr, nullptr));

  d_ = dofs_.create_global();
  b_ = dofs_.create_global();
  lift_ = dofs_.create_global();
  d_loc_ = dofs_.create_local();
  TF_PETSC(KSPCreate(dmesh.comm(), ksp_.out()));
  TF_PETSC(KSPSetOptionsPrefix(ksp_, "mesh_"));
  TF_PETSC(KSPSetOperators(ksp_, A_, A_));
  TF_PETSC(KSPSetType(ksp_, KSPCG));
  PC pc;
  TF_PETSC(KSPGetPC(ksp_, &pc));
  TF_PETSC(PCSetType(pc, PCHYPRE));
  // The fluid's BoomerAMG settings for 3D (HMIS / ext+i), unless the user set any.
  fem::set_default_options(fem::boomeramg_3d_options("-mesh_"));
  // The displacement enters the fluid's geometry, so its error is a residual error of the
  // FSI system: solve below the Newton tolerance. Any interior displacement is a valid ALE
  // map (the wall's nodes are set exactly, and x and w come from the same d), so the solve's
  // error only has to stay below Newton's: 1e-6 relative to the lifted wall motion left
  // pipe-fsi's Newton residual histories unchanged to three digits against 1e-8 (and 1e-8
  // against 1e-10), 0.6 s/step faster on 2 ranks (37 -> 24 CG iterations per step).
  TF_PETSC(KSPSetTolerances(ksp_, 1e-6, 1e-20, PETSC_DEFAULT, 1000));
  TF_PETSC(KSPSetInitialGuessNonzero(ksp_, PETSC_TRUE));
  TF_PETSC(KSPSetFromOptions(ksp_));
}

void MeshMotion::start_from(const std::vector<Vec3>& d) {
  fem::WriteArray guess(d_);
  for (Index l = 0; l < dmesh_.num_owned(); ++l)
    if (role_[l] == Role::Free)
      for (int c = 0; c < 3; ++c)
        guess[3 * l + c] = d[l][c];
}

void MeshMotion::solve(const std::vector<Vec3>& wall, std::vector<Vec3>& out) {
  {
    fem::WriteArray lift(lift_);
    for (Index l = 0; l < dmesh_.num_owned(); ++l)
      for (int c = 0; c < 3; ++c)
        lift[3 * l + c] = role_[l] == Role::Wall ? wall[l][c] : 0.0;
  }
  TF_PETSC(MatMult(A0_, lift_, b_));
  TF_PETSC(VecScale(b_, -1.0));
  {
    fem::WriteArray b(b_), d(d_);
    fem::ReadArray lift(lift_);
    for (Index l = 0; l < dmesh_.num_owned(); ++l)
      if (role_[l] != Role::Free)
        for (int c = 0; c < 3; ++c) {
          b[3 * l + c] = lift[3 * l + c];
          d[3 * l + c] = lift[3 * l + c];
        }
  }
  TF_PETSC(KSPSolve(ksp_, b_, d_));
  KSPConvergedReason reason;
  TF_PETSC(KSPGetConvergedReason(ksp_, &reason));
  PetscInt its = 0;
  TF_PETSC(KSPGetIterationNumber(ksp_, &its));
  iterations_ = static_cast<int>(its);
  if (reason < 0)
    throw SolverError(fmt::format("mesh motion: the linear solve failed ({}) after {} iterations",
                                  KSPConvergedReasons[reason], its));
  dofs_.global_to_local(d_, d_loc_);
  fem::ReadArray d(d_loc_);
  out.resize(role_.size());
  for (Index l = 0; l < dmesh_.num_local(); ++l)
    for (int c = 0; c < 3; ++c)
      out[l][c] = role_[l] == Role::Wall ? wall[l][c] : d[3 * l + c];
}

} // namespace tearflow::physics
