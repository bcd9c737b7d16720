#include "physics/solid_problem.hpp"

#include <algorithm>
#include <cmath>

#include "bc/face_geometry.hpp"
#include "core/names.hpp"

namespace tearflow::physics {

namespace {

/// Index of the face called `name` in dmesh.faces(); InputError naming `what` otherwise.
size_t face_index(const fem::DistributedMesh& dmesh, const std::string& name, const char* what) {
  const auto& faces = dmesh.faces();
  for (size_t i = 0; i < faces.size(); ++i)
    if (faces[i].name == name)
      return i;
  std::vector<std::string> names;
  for (const auto& f : faces)
    names.push_back(f.name);
  input_error("{} on face '{}': the mesh has no such face; its faces are {}", what, name,
              join_names(names, "and"));
}

double triangle_area(const std::vector<Vec3>& x, const Tri& t) {
  const Vec3 c = cross(x[t[1]] - x[t[0]], x[t[2]] - x[t[0]]);
  return 0.5 * std::sqrt(dot(c, c));
}

} // namespace

SolidProblem::SolidProblem(const mesh::Mesh& mesh, const fem::DistributedMesh& dmesh,
                           SolidMaterial material, bc::SolidConditions conditions,
                           SolidScheme scheme, FieldLayout layout)
    : dmesh_(dmesh), layout_(layout), B_(layout.block), P_(layout.pressure),
      elements_(layout.elements(dmesh)), dofs_(dmesh, layout.block), inserter_(dofs_),
      material_(material), conditions_(std::move(conditions)), scheme_(scheme) {
  const auto n_local = static_cast<size_t>(dmesh.num_local());
  const auto& x = dmesh.points();
  geometry_.resize(dmesh.tets().size());
  rows_.resize(geometry_.size());
  double sums[2] = {0.0, static_cast<double>(elements_.size())}; // volume, tets
  for (size_t e : elements_) {
    const Tet& t = dmesh.tets()[e];
    geometry_[e] = fem::tet_geometry({x[t[0]], x[t[1]], x[t[2]], x[t[3]]});
    sums[0] += geometry_[e].volume;
  }
  MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, dmesh.comm());
  // s = mu / h makes the pressure row a force: s (J - 1) V ~ kappa (J - 1) h^2 ~ sigma h^2.
  row_scale_ = material_.mu / std::cbrt(6.0 * std::sqrt(2.0) * sums[0] / sums[1]);
  for (size_t e : elements_)
    rows_[e] = {pressure_stabilization(material_, geometry_[e].volume), row_scale_};

  // Prescribed components on every local node, from the replicated faces, so that all ranks
  // agree on the skipped rows. Where faces meet, each keeps its own components.
  std::vector<Index> orig_to_local(mesh.num_nodes(), -1);
  for (Index l = 0; l < dmesh.num_local(); ++l)
    orig_to_local[dmesh.original_index(l)] = l;
  dirichlet_.assign(n_local, 0);
  std::vector<std::array<int, 3>> spec_of(n_local, {-1, -1, -1});
  for (size_t s = 0; s < conditions_.fixed.size(); ++s) {
    const bc::FixedFace& f = conditions_.fixed[s];
    face_index(dmesh, f.face, "fixed condition"); // a clear message for an unknown face
    for (const Tri& t : mesh.face(f.face).triangles)
      for (Index v : t)
        if (Index l = orig_to_local[v]; l >= 0)
          for (int c = 0; c < 3; ++c)
            if ((f.components >> c) & 1) {
              dirichlet_[l] |= static_cast<std::uint8_t>(1u << c);
              spec_of[l][c] = static_cast<int>(s);
            }
  }
  for (Index l = 0; l < dmesh.num_owned(); ++l)
    for (int c = 0; c < 3; ++c)
      if (spec_of[l][c] >= 0)
        fixed_nodes_.push_back({l, c, static_cast<size_t>(spec_of[l][c])});
  for (const bc::PressureLoad& p : conditions_.loads)
    load_faces_.push_back(face_index(dmesh, p.face, "pressure load"));
  for (const bc::RobinSupport& r : conditions_.supports)
    support_faces_.push_back(face_index(dmesh, r.face, "tissue support (robin)"));

  U_loc_ = dofs_.create_local();
  R_loc_ = dofs_.create_local();
  Un_loc_ = dofs_.create_local();
  Dn_loc_ = dofs_.create_local();
  An_loc_ = dofs_.create_local();
  u_af_.resize(n_local);
  v_af_.resize(n_local);
  a_am_.resize(n_local);
  p_.resize(n_local);
}

PetscInt SolidProblem::row_index(Index l, int c) const {
  return (c < 3 && (dirichlet_[l] >> c) & 1) ? -1 : dofs_.global_dof(l, c);
}

std::vector<PetscInt> SolidProblem::dirichlet_rows() const {
  std::vector<PetscInt> rows;
  for (const FixedNode& f : fixed_nodes_)
    rows.push_back(dofs_.global_dof(f.local, f.comp));
  return rows;
}

double SolidProblem::load_time() const {
  return t_n_ + (scheme_.quasi_static ? 1.0 : scheme_.alpha_f) * dt_;
}

void SolidProblem::begin_step(double t_n, double dt, Vec U_n, Vec D_n, Vec A_n) {
  t_n_ = t_n;
  dt_ = dt;
  dofs_.global_to_local(U_n, Un_loc_);
  dofs_.global_to_local(D_n, Dn_loc_);
  dofs_.global_to_local(A_n, An_loc_);

  // v_{n+1} that puts u_{n+1} = u_bar + c v_{n+1} on g(t_{n+1}).
  fem::ReadArray vn(Un_loc_), un(Dn_loc_), an(An_loc_);
  const auto [am, af, gamma, beta, quasi_static] = scheme_;
  const double c = quasi_static ? dt : beta * dt / gamma;
  dirichlet_target_.resize(fixed_nodes_.size());
  for (size_t k = 0; k < fixed_nodes_.size(); ++k) {
    const FixedNode& f = fixed_nodes_[k];
    const PetscInt i = B_ * f.local + f.comp;
    const double g = conditions_.fixed[f.spec].at(t_n + dt)[f.comp];
    const double u_bar = quasi_static ? un[i]
                                      : un[i] + dt * vn[i] + dt * dt * (0.5 - beta) * an[i] -
                                            c * (vn[i] + dt * (1.0 - gamma) * an[i]);
    dirichlet_target_[k] = (g - u_bar) / c;
  }
}

void SolidProblem::apply_dirichlet(Vec U) const {
  fem::WriteArray u(U);
  for (size_t k = 0; k < fixed_nodes_.size(); ++k)
    u[B_ * fixed_nodes_[k].local + fixed_nodes_[k].comp] = dirichlet_target_[k];
}

void SolidProblem::stage(Vec U) {
  dofs_.global_to_local(U, U_loc_);
  fem::ReadArray v(U_loc_), vn(Un_loc_), un(Dn_loc_), an(An_loc_);
  const auto [am, af, gamma, beta, quasi_static] = scheme_;
  for (Index l = 0; l < dmesh_.num_local(); ++l) {
    for (int c = 0; c < 3; ++c) {
      const PetscInt i = B_ * l + c;
      if (quasi_static) {
        u_af_[l][c] = un[i] + dt_ * v[i];
        v_af_[l][c] = v[i];
        a_am_[l][c] = 0.0;
        continue;
      }
      const double a1 = (v[i] - vn[i]) / (gamma * dt_) - (1.0 - gamma) / gamma * an[i];
      const double u1 = un[i] + dt_ * vn[i] + dt_ * dt_ * ((0.5 - beta) * an[i] + beta * a1);
      u_af_[l][c] = un[i] + af * (u1 - un[i]);
      v_af_[l][c] = vn[i] + af * (v[i] - vn[i]);
      a_am_[l][c] = an[i] + am * (a1 - an[i]);
    }
    p_[l] = v[B_ * l + P_];
  }
}

void SolidProblem::gather(const Tet& t, SolidElementState& s) const {
  for (int a = 0; a < 4; ++a) {
    s.u[a] = u_af_[t[a]];
    s.a[a] = a_am_[t[a]];
    s.p[a] = p_[t[a]];
  }
}

std::array<Vec3, 3> SolidProblem::deformed(const Tri& t) const {
  const auto& X = dmesh_.points();
  return {X[t[0]] + u_af_[t[0]], X[t[1]] + u_af_[t[1]], X[t[2]] + u_af_[t[2]]};
}

void SolidProblem::residual(Vec U, Vec R) {
  TF_PETSC(VecZeroEntries(R_loc_));
  add_residual(U, R_loc_);
  TF_PETSC(VecZeroEntries(R));
  dofs_.add_local_to_global(R_loc_, R);
  set_dirichlet_residual(U, R);
}

void SolidProblem::add_residual(Vec U, Vec R_loc) {
  stage(U);
  {
    fem::WriteArray r(R_loc);
    const auto& tets = dmesh_.tets();
    const std::array<int, 4> slot = layout_.slots();
    SolidElementState s;
    ElementVector Re;
    for (size_t e : elements_) {
      const Tet& t = tets[e];
      gather(t, s);
      solid_residual(geometry_[e], s, material_, rows_[e], Re);
      for (int a = 0; a < 4; ++a)
        for (int c = 0; c < 4; ++c)
          r[B_ * t[a] + slot[c]] += Re[4 * a + c];
    }
    auto add_triangle = [&](const Tri& t, const bc::TriVector& Rt) {
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c)
          r[B_ * t[a] + c] += Rt[3 * a + c];
    };
    const double t_load = load_time();
    for (size_t i = 0; i < load_faces_.size(); ++i) {
      const double P = conditions_.loads[i].pressure(t_load);
      for (const Tri& t : dmesh_.faces()[load_faces_[i]].triangles) {
        bc::TriVector Rt{};
        bc::follower_pressure_residual(deformed(t), P, Rt);
        add_triangle(t, Rt);
      }
    }
    for (size_t i = 0; i < support_faces_.size(); ++i) {
      const bc::RobinSupport& sup = conditions_.supports[i];
      for (const Tri& t : dmesh_.faces()[support_faces_[i]].triangles) {
        bc::TriVector Rt{};
        bc::robin_residual(triangle_area(dmesh_.points(), t),
                           {u_af_[t[0]], u_af_[t[1]], u_af_[t[2]]},
                           {v_af_[t[0]], v_af_[t[1]], v_af_[t[2]]}, sup.stiffness, sup.damping, Rt);
        if (sup.pressure != 0.0)
          bc::follower_pressure_residual(deformed(t), sup.pressure, Rt);
        add_triangle(t, Rt);
      }
    }
  }
}

void SolidProblem::set_dirichlet_residual(Vec U, Vec R) const {
  // Dirichlet rows: R = v - v_target.
  fem::WriteArray r(R);
  fem::ReadArray v(U);
  for (size_t k = 0; k < fixed_nodes_.size(); ++k) {
    const PetscInt i = B_ * fixed_nodes_[k].local + fixed_nodes_[k].comp;
    r[i] = v[i] - dirichlet_target_[k];
  }
}

void SolidProblem::jacobian(Vec U, Mat J) {
  TF_PETSC(MatZeroEntries(J));
  add_jacobian(U, J);
  for (const FixedNode& f : fixed_nodes_) {
    const PetscInt d = dofs_.global_dof(f.local, f.comp);
    TF_PETSC(MatSetValue(J, d, d, 1.0, ADD_VALUES));
  }
  TF_PETSC(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
  TF_PETSC(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
}

void SolidProblem::add_jacobian(Vec U, Mat J, bool skip_dirichlet_rows) {
  stage(U);
  const double c_u = scheme_.c_u(dt_), c_v = scheme_.c_v(), c_a = scheme_.c_a(dt_);
  const auto& tets = dmesh_.tets();
  SolidElementState s;
  ElementMatrix K;
  // Whole node blocks (4 B_ unknowns per element, zeros in the other physics' slot), so that
  // the assembled pattern stays node-blocked. Without skipped rows (FSI: the caller replaces
  // the Dirichlet rows) they go in by direct insertion, after the fluid's in the same pass.
  const int n = 4 * B_;
  std::vector<PetscInt> rows(n), cols(n);
  std::vector<double> Kx(B_ == 4 ? 0 : static_cast<size_t>(n) * n);
  if (!skip_dirichlet_rows)
    inserter_.begin(J, false);
  for (size_t e : elements_) {
    const Tet& t = tets[e];
    gather(t, s);
    solid_jacobian(geometry_[e], s, material_, rows_[e], c_u, c_a, K);
    if (B_ != 4)
      expand_element_matrix(&K[0][0], layout_, Kx.data());
    const double* Ke = B_ == 4 ? &K[0][0] : Kx.data();
    if (!skip_dirichlet_rows) {
      inserter_.add(e, Ke);
      continue;
    }
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < B_; ++c) {
        rows[B_ * a + c] = row_index(t[a], c);
        cols[B_ * a + c] = dofs_.global_dof(t[a], c);
      }
    TF_PETSC(MatSetValues(J, n, rows.data(), n, cols.data(), Ke, ADD_VALUES));
  }
  if (!skip_dirichlet_rows)
    inserter_.end();

  std::array<PetscInt, 9> trows, tcols;
  auto insert_triangle = [&](const Tri& t, const bc::TriMatrix& Kt) {
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c) {
        trows[3 * a + c] = row_index(t[a], c);
        tcols[3 * a + c] = dofs_.global_dof(t[a], c);
      }
    TF_PETSC(MatSetValues(J, 9, trows.data(), 9, tcols.data(), &Kt[0][0], ADD_VALUES));
  };
  const double t_load = load_time();
  for (size_t i = 0; i < load_faces_.size(); ++i) {
    const double P = conditions_.loads[i].pressure(t_load);
    for (const Tri& t : dmesh_.faces()[load_faces_[i]].triangles) {
      bc::TriMatrix Kt{};
      bc::follower_pressure_jacobian(deformed(t), P, c_u, Kt);
      insert_triangle(t, Kt);
    }
  }
  for (size_t i = 0; i < support_faces_.size(); ++i) {
    const bc::RobinSupport& sup = conditions_.supports[i];
    for (const Tri& t : dmesh_.faces()[support_faces_[i]].triangles) {
      bc::TriMatrix Kt{};
      bc::robin_jacobian(triangle_area(dmesh_.points(), t), sup.stiffness, sup.damping, c_u, c_v,
                         Kt);
      if (sup.pressure != 0.0)
        bc::follower_pressure_jacobian(deformed(t), sup.pressure, c_u, Kt);
      insert_triangle(t, Kt);
    }
  }
}

void SolidProblem::update_state(Vec U_next, Vec D, Vec A) const {
  const auto [am, af, gamma, beta, quasi_static] = scheme_;
  fem::ReadArray v(U_next), vn(Un_loc_); // Un_loc_: owned entries first, in global order
  fem::WriteArray u(D), a(A);
  for (Index l = 0; l < dmesh_.num_owned(); ++l)
    for (int c = 0; c < 3; ++c) {
      const PetscInt i = B_ * l + c;
      if (quasi_static) {
        u[i] += dt_ * v[i];
        a[i] = 0.0;
        continue;
      }
      const double a1 = (v[i] - vn[i]) / (gamma * dt_) - (1.0 - gamma) / gamma * a[i];
      u[i] += dt_ * vn[i] + dt_ * dt_ * ((0.5 - beta) * a[i] + beta * a1);
      a[i] = a1;
    }
}

std::vector<FaceDisplacement> SolidProblem::measure_faces(Vec D) const {
  fem::OwnedVec D_loc = dofs_.create_local();
  dofs_.global_to_local(D, D_loc);
  fem::ReadArray u(D_loc);
  const auto& x = dmesh_.points();
  std::vector<double> sums;
  for (const fem::LocalFace& f : dmesh_.faces()) {
    double s[4] = {0.0, 0.0, 0.0, 0.0}; // int u_c dA, area
    for (const Tri& t : f.triangles) {
      const double area = triangle_area(x, t);
      s[3] += area;
      for (Index l : t)
        for (int c = 0; c < 3; ++c)
          s[c] += area / 3.0 * u[B_ * l + c];
    }
    sums.insert(sums.end(), s, s + 4);
  }
  MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_DOUBLE, MPI_SUM,
                dmesh_.comm());
  std::vector<FaceDisplacement> out;
  for (size_t i = 0; i < dmesh_.faces().size(); ++i) {
    const double* s = &sums[4 * i];
    out.push_back({dmesh_.faces()[i].name, {s[0] / s[3], s[1] / s[3], s[2] / s[3]}, s[3]});
  }
  return out;
}

SolidEnergy SolidProblem::stage_energy(Vec U) {
  stage(U);
  SolidEnergy E;
  const auto& tets = dmesh_.tets();
  SolidElementState s;
  for (size_t e : elements_) {
    const Tet& t = tets[e];
    gather(t, s);
    E.stored += solid_stored_energy(geometry_[e], s, material_, rows_[e]);
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        E.kinetic += 0.5 * material_.density * fem::mass(geometry_[e].volume, a, b) *
                     dot(v_af_[t[a]], v_af_[t[b]]);
  }
  for (size_t i = 0; i < support_faces_.size(); ++i)
    for (const Tri& t : dmesh_.faces()[support_faces_[i]].triangles) {
      const double area = triangle_area(dmesh_.points(), t);
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
          E.support += 0.5 * conditions_.supports[i].stiffness * area / 12.0 *
                       (a == b ? 2.0 : 1.0) * dot(u_af_[t[a]], u_af_[t[b]]);
    }
  double sums[3] = {E.kinetic, E.stored, E.support};
  MPI_Allreduce(MPI_IN_PLACE, sums, 3, MPI_DOUBLE, MPI_SUM, dmesh_.comm());
  return {sums[0], sums[1], sums[2]};
}

void SolidProblem::nodal_stress(Vec U, Vec D, Vec out) const {
  fem::OwnedVec U_loc = dofs_.create_local(), D_loc = dofs_.create_local(),
                S_loc = dofs_.create_local();
  dofs_.global_to_local(U, U_loc);
  dofs_.global_to_local(D, D_loc);
  {
    fem::ReadArray v(U_loc), u(D_loc);
    fem::WriteArray acc(S_loc); // per node: V sigma_vM, V J, V
    const auto& tets = dmesh_.tets();
    std::array<Vec3, 4> ue;
    for (size_t e : elements_) {
      const Tet& t = tets[e];
      double p = 0.0;
      for (int a = 0; a < 4; ++a) {
        ue[a] = {u[B_ * t[a]], u[B_ * t[a] + 1], u[B_ * t[a] + 2]};
        p += 0.25 * v[B_ * t[a] + P_];
      }
      const Mat3 F = deformation_gradient(geometry_[e], ue);
      const double V = geometry_[e].volume;
      const double vm = von_mises(cauchy_stress(material_, F, p));
      for (Index l : t) {
        acc[B_ * l] += V * vm;
        acc[B_ * l + 1] += V * det(F);
        acc[B_ * l + 2] += V;
      }
    }
  }
  TF_PETSC(VecZeroEntries(out));
  dofs_.add_local_to_global(S_loc, out);
  fem::WriteArray o(out);
  for (Index l = 0; l < dmesh_.num_owned(); ++l) {
    const double w = o[B_ * l + 2];
    if (w == 0.0) // a node of no solid tet (the fluid of an FSI mesh)
      continue;
    o[B_ * l] /= w;
    o[B_ * l + 1] /= w;
    o[B_ * l + 2] = 0.0;
  }
}

} // namespace tearflow::physics
