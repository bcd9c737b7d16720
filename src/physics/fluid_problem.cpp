#include "physics/fluid_problem.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "bc/face_geometry.hpp"

namespace tearflow::physics {

namespace {
constexpr std::uint8_t all_velocity = 0b111;
} // namespace

FluidProblem::FluidProblem(const mesh::Mesh& mesh, const fem::DistributedMesh& dmesh,
                           FluidProperties fluid, bc::FluidConditions conditions,
                           GeneralizedAlpha scheme, FieldLayout layout)
    : dmesh_(dmesh), layout_(layout), B_(layout.block), P_(layout.pressure),
      dofs_(dmesh, layout.block), inserter_(dofs_), fluid_(fluid),
      conditions_(std::move(conditions)), scheme_(scheme), flux_dofs_(dmesh, flux_block) {
  const auto n_local = static_cast<size_t>(dmesh.num_local());
  elements_ = layout_.elements(dmesh);
  // Faces of the fluid: every node on a fluid tet (from the replicated mesh, so that all
  // ranks agree); with a wall region, its own faces are not the fluid's.
  {
    std::vector<unsigned char> in_fluid(mesh.num_nodes(), layout_.region < 0);
    if (layout_.region >= 0)
      for (size_t e = 0; e < mesh.tets.size(); ++e)
        if (mesh.tet_region[e] == layout_.region)
          for (Index v : mesh.tets[e])
            in_fluid[v] = 1;
    for (const fem::LocalFace& f : dmesh.faces()) {
      bool all = true;
      for (const Tri& t : mesh.face(f.name).triangles)
        all = all && in_fluid[t[0]] && in_fluid[t[1]] && in_fluid[t[2]];
      fluid_face_.push_back(all);
    }
  }
  x_ = dmesh.points();
  w_.assign(n_local, Vec3{});
  geometry_.resize(dmesh.tets().size());
  for (size_t e : elements_) {
    const Tet& t = dmesh.tets()[e];
    geometry_[e] = fem::tet_geometry({x_[t[0]], x_[t[1]], x_[t[2]], x_[t[3]]});
  }
  stab_.resize(geometry_.size());

  // Dirichlet flags on every local node, from the replicated faces, so that all ranks agree
  // on which rows are skipped. No-slip wins over inflow on the inlet's rim.
  std::vector<Index> orig_to_local(mesh.num_nodes(), -1);
  for (Index l = 0; l < dmesh.num_local(); ++l)
    orig_to_local[dmesh.original_index(l)] = l;
  dirichlet_.assign(n_local, 0);
  std::vector<std::uint8_t> is_wall(n_local, 0);
  for (const std::string& name : conditions_.walls)
    for (const Tri& t : mesh.face(name).triangles)
      for (Index v : t)
        if (Index l = orig_to_local[v]; l >= 0) {
          dirichlet_[l] = all_velocity;
          is_wall[l] = 1;
        }
  for (size_t i = 0; i < conditions_.inflows.size(); ++i) {
    const auto& nodes = conditions_.inflows[i].nodes();
    for (size_t k = 0; k < nodes.size(); ++k)
      if (Index l = orig_to_local[nodes[k]]; l >= 0 && !is_wall[l]) {
        dirichlet_[l] = all_velocity;
        if (l < dmesh.num_owned())
          inflow_nodes_.push_back({l, i, k});
      }
  }
  for (Index l = 0; l < dmesh.num_owned(); ++l) {
    if (is_wall[l])
      wall_nodes_.push_back(l);
    for (int c = 0; c < 3; ++c)
      if ((dirichlet_[l] >> c) & 1)
        dirichlet_rows_.push_back(dofs_.global_dof(l, c));
  }

  for (const bc::TractionOutlet& spec : conditions_.outlets) {
    OutletData o{spec, 0, dofs_.create_global(), 0.0, {bc::initial_state(spec.law), 0.0}, {}};
    const auto& faces = dmesh.faces();
    o.face_index = std::find_if(faces.begin(), faces.end(),
                                [&](const fem::LocalFace& f) { return f.name == spec.face; }) -
                   faces.begin();
    outlets_.push_back(std::move(o));
  }
  compute_outlet_vectors();

  U_loc_ = dofs_.create_local();
  R_loc_ = dofs_.create_local();
  Un_loc_ = dofs_.create_local();
  Udotn_loc_ = dofs_.create_local();
  u_af_.resize(n_local);
  udot_am_.resize(n_local);
  p_.resize(n_local);
  if (fluid_.stabilization.viscous_correction) {
    flux_loc_ = flux_dofs_.create_local();
    flux_global_ = flux_dofs_.create_global();
    nodal_flux_.resize(n_local);
  }
}

void FluidProblem::compute_outlet_vectors() {
  // v_ai = int N_a n_i over this rank's triangles, summed into the global vector.
  for (OutletData& o : outlets_) {
    fem::OwnedVec v_loc = dofs_.create_local();
    {
      fem::WriteArray v(v_loc);
      for (const Tri& t : dmesh_.faces()[o.face_index].triangles) {
        double area;
        Vec3 n;
        bc::triangle_area_normal(x_[t[0]], x_[t[1]], x_[t[2]], area, n);
        for (Index l : t)
          for (int c = 0; c < 3; ++c)
            if (!((dirichlet_[l] >> c) & 1))
              v[B_ * l + c] += area / 3.0 * n[c];
      }
    }
    TF_PETSC(VecZeroEntries(o.v));
    dofs_.add_local_to_global(v_loc, o.v);
  }
}

void FluidProblem::move_mesh(const std::vector<Vec3>& x, const std::vector<Vec3>& w) {
  x_ = x;
  w_ = w;
  const auto& tets = dmesh_.tets();
  for (size_t e : elements_) {
    const Tet& t = tets[e];
    geometry_[e] = fem::tet_geometry({x_[t[0]], x_[t[1]], x_[t[2]], x_[t[3]]});
  }
  compute_outlet_vectors();
}

void FluidProblem::begin_step(double t_n, double dt, Vec U_n, Vec Udot_n) {
  t_n_ = t_n;
  dt_ = dt;
  dofs_.global_to_local(U_n, Un_loc_);
  dofs_.global_to_local(Udot_n, Udotn_loc_);
  fem::ReadArray un(Un_loc_);
  const auto& tets = dmesh_.tets();
  for (size_t e : elements_) {
    Vec3 mean{}; // the convective velocity u_n - w
    for (Index l : tets[e])
      for (int c = 0; c < 3; ++c)
        mean[c] += 0.25 * (un[B_ * l + c] - w_[l][c]);
    stab_[e] = stabilization(geometry_[e], mean, fluid_, dt);
  }
  if (fluid_.stabilization.viscous_correction) {
    // sigma_h from the predictor u_n + alpha_f dt udot_n of u_{n+af}, like tau_M on the mesh
    // at t_n (navier_stokes_kernel.hpp); u_af_ holds it until the first stage().
    fem::ReadArray udn(Udotn_loc_);
    for (Index l = 0; l < dmesh_.num_local(); ++l)
      for (int c = 0; c < 3; ++c)
        u_af_[l][c] = un[B_ * l + c] + scheme_.alpha_f * dt * udn[B_ * l + c];
    reconstruct_viscous_flux();
  }
  const bc::StepClock clock{t_n, dt, scheme_.alpha_f};
  for (OutletData& o : outlets_)
    o.law = bc::step_law(o.spec.law, o.state.law, o.state.flux, clock);
}

template <typename Velocity>
std::vector<double> FluidProblem::outlet_fluxes(Velocity&& velocity) const {
  const auto& x = x_;
  std::vector<double> q(outlets_.size(), 0.0);
  for (size_t i = 0; i < outlets_.size(); ++i)
    for (const Tri& t : dmesh_.faces()[outlets_[i].face_index].triangles) {
      double area;
      Vec3 n;
      bc::triangle_area_normal(x[t[0]], x[t[1]], x[t[2]], area, n);
      q[i] += area / 3.0 * dot(velocity(t[0]) + velocity(t[1]) + velocity(t[2]), n);
    }
  MPI_Allreduce(MPI_IN_PLACE, q.data(), static_cast<int>(q.size()), MPI_DOUBLE, MPI_SUM,
                dmesh_.comm());
  return q;
}

void FluidProblem::commit_step(Vec U_next) {
  dofs_.global_to_local(U_next, U_loc_);
  std::vector<double> q_next;
  {
    fem::ReadArray u(U_loc_);
    q_next = outlet_fluxes([&](Index l) { return Vec3{u[B_ * l], u[B_ * l + 1], u[B_ * l + 2]}; });
  }
  for (size_t i = 0; i < outlets_.size(); ++i) {
    OutletData& o = outlets_[i];
    o.state.law = bc::commit(o.spec.law, o.state.law, o.state.flux, q_next[i], dt_);
    o.state.flux = q_next[i];
  }
}

double FluidProblem::peak_inflow() const {
  // The waveform's samples and its spline between them: 720 points over a period.
  constexpr int samples = 720;
  double peak = 0.0;
  for (const bc::InflowProfile& in : conditions_.inflows) {
    const bc::Waveform& q = in.flow();
    for (int i = 0; i < samples; ++i)
      peak = std::max(peak, std::abs(q(q.period() * i / samples)));
  }
  return peak;
}

bool FluidProblem::has_coupled_outlets() const {
  return std::any_of(outlets_.begin(), outlets_.end(),
                     [](const OutletData& o) { return bc::coupled(o.spec.law); });
}

std::vector<FluidProblem::OutletState> FluidProblem::outlet_states() const {
  std::vector<OutletState> s;
  for (const OutletData& o : outlets_)
    s.push_back(o.state);
  return s;
}

void FluidProblem::set_outlet_law(size_t i, const bc::OutletLaw& law) {
  if (i >= outlets_.size() || !bc::same_law(outlets_[i].spec.law, law))
    throw std::logic_error("set_outlet_law: outlet " + std::to_string(i) +
                           " has another law; its state would not fit");
  outlets_[i].spec.law = law;
  conditions_.outlets[i].law = law;
}

void FluidProblem::set_outlet_states(const std::vector<OutletState>& states) {
  if (states.size() != outlets_.size())
    input_error("{} outlet states given for {} outlets", states.size(), outlets_.size());
  for (size_t i = 0; i < outlets_.size(); ++i) {
    if (states[i].law.index() != outlets_[i].state.law.index())
      throw std::logic_error("set_outlet_states: a state of another outlet law");
    outlets_[i].state = states[i];
  }
}

void FluidProblem::apply_dirichlet(Vec U) const {
  const double t = t_n_ + dt_;
  fem::WriteArray u(U);
  for (Index l : wall_nodes_)
    for (int c = 0; c < 3; ++c)
      u[B_ * l + c] = 0.0;
  for (const InflowNode& n : inflow_nodes_) {
    const Vec3 g = conditions_.inflows[n.inflow].velocity(n.k, t);
    for (int c = 0; c < 3; ++c)
      u[B_ * n.local + c] = g[c];
  }
}

void FluidProblem::stage(Vec U) {
  dofs_.global_to_local(U, U_loc_);
  fem::ReadArray u(U_loc_), un(Un_loc_), udn(Udotn_loc_);
  const auto [am, af, gamma] = scheme_;
  for (Index l = 0; l < dmesh_.num_local(); ++l) {
    for (int c = 0; c < 3; ++c) {
      const PetscInt i = B_ * l + c;
      const double udot_next = (u[i] - un[i]) / (gamma * dt_) - (1.0 - gamma) / gamma * udn[i];
      u_af_[l][c] = un[i] + af * (u[i] - un[i]);
      udot_am_[l][c] = udn[i] + am * (udot_next - udn[i]);
    }
    p_[l] = u[B_ * l + P_];
  }
}

void FluidProblem::reconstruct_viscous_flux() {
  if (!fluid_.stabilization.viscous_correction)
    return;
  const auto& tets = dmesh_.tets();
  TF_PETSC(VecZeroEntries(flux_loc_));
  {
    fem::WriteArray f(flux_loc_);
    for (size_t e : elements_) {
      const Tet& t = tets[e];
      const SymTensor sigma = viscous_flux(
          geometry_[e], {u_af_[t[0]], u_af_[t[1]], u_af_[t[2]], u_af_[t[3]]}, fluid_.viscosity);
      const double share = 0.25 * geometry_[e].volume; // the row sum of the P1 mass matrix
      for (Index l : t) {
        double* node = &f[flux_block * l];
        for (int k = 0; k < 6; ++k)
          node[k] += share * sigma[k];
        node[6] += share;
      }
    }
  }
  TF_PETSC(VecZeroEntries(flux_global_));
  flux_dofs_.add_local_to_global(flux_loc_, flux_global_);
  flux_dofs_.global_to_local(flux_global_, flux_loc_);
  fem::ReadArray f(flux_loc_);
  for (Index l = 0; l < dmesh_.num_local(); ++l) {
    const double* node = &f[flux_block * l];
    for (int k = 0; k < 6; ++k) // nodes of no fluid tet (an FSI wall's) keep zero
      nodal_flux_[l][k] = node[6] > 0.0 ? node[k] / node[6] : 0.0;
  }
}

void FluidProblem::gather(size_t e, FluidElementState& s) const {
  const Tet& t = dmesh_.tets()[e];
  for (int a = 0; a < 4; ++a) {
    s.u[a] = u_af_[t[a]];
    s.udot[a] = udot_am_[t[a]];
    s.p[a] = p_[t[a]];
    s.w[a] = w_[t[a]];
  }
  s.viscous = nodal_flux_.empty()
                  ? Vec3{}
                  : flux_divergence(geometry_[e], {nodal_flux_[t[0]], nodal_flux_[t[1]],
                                                   nodal_flux_[t[2]], nodal_flux_[t[3]]});
}

void FluidProblem::update_outlet_fluxes() {
  const std::vector<double> q = outlet_fluxes([&](Index l) { return u_af_[l]; });
  for (size_t i = 0; i < outlets_.size(); ++i)
    outlets_[i].flux = q[i];
}

double FluidProblem::outlet_pressure(const OutletData& o) const {
  return o.law.p0 + o.law.resistance * o.flux;
}

void FluidProblem::residual(Vec U, Vec R) {
  TF_PETSC(VecZeroEntries(R_loc_));
  add_residual(U, R_loc_);
  TF_PETSC(VecZeroEntries(R));
  dofs_.add_local_to_global(R_loc_, R);
  set_dirichlet_residual(U, R);
}

void FluidProblem::add_residual(Vec U, Vec R_loc) {
  stage(U);
  update_outlet_fluxes();
  {
    fem::WriteArray r(R_loc);
    const auto& tets = dmesh_.tets();
    const std::array<int, 4> slot = layout_.slots();
    FluidElementState s;
    ElementVector Re;
    for (size_t e : elements_) {
      const Tet& t = tets[e];
      gather(e, s);
      navier_stokes_residual(geometry_[e], s, stab_[e], fluid_, Re);
      for (int a = 0; a < 4; ++a)
        for (int c = 0; c < 4; ++c)
          r[B_ * t[a] + slot[c]] += Re[4 * a + c];
    }

    // Outlets: -<w, h> = +int N_a P n_i - beta rho int N_a (u.n)_- u_i, the backflow term by
    // the edge-midpoint rule (exact for the quadratic integrand where u.n keeps its sign).
    const auto& x = x_;
    for (const OutletData& o : outlets_) {
      const double P = outlet_pressure(o);
      const double bf = o.spec.backflow_beta * fluid_.density;
      for (const Tri& t : dmesh_.faces()[o.face_index].triangles) {
        double area;
        Vec3 n;
        bc::triangle_area_normal(x[t[0]], x[t[1]], x[t[2]], area, n);
        for (int a = 0; a < 3; ++a)
          for (int c = 0; c < 3; ++c)
            r[B_ * t[a] + c] += area / 3.0 * P * n[c];
        if (bf == 0.0)
          continue;
        for (int q = 0; q < 3; ++q) { // midpoint of edge (q, q+1)
          const int a0 = q, a1 = (q + 1) % 3;
          const Vec3 uq = 0.5 * (u_af_[t[a0]] + u_af_[t[a1]]);
          const double un = dot(uq, n);
          if (un >= 0.0)
            continue;
          for (int a : {a0, a1})
            for (int c = 0; c < 3; ++c)
              r[B_ * t[a] + c] -= bf * area / 3.0 * 0.5 * un * uq[c];
        }
      }
    }
  }
}

void FluidProblem::set_dirichlet_residual(Vec U, Vec R) const {
  // Dirichlet rows: R = U - g(t_{n+1}).
  const double t = t_n_ + dt_;
  fem::WriteArray r(R);
  fem::ReadArray u(U);
  for (Index l : wall_nodes_)
    for (int c = 0; c < 3; ++c)
      r[B_ * l + c] = u[B_ * l + c];
  for (const InflowNode& nd : inflow_nodes_) {
    const Vec3 g = conditions_.inflows[nd.inflow].velocity(nd.k, t);
    for (int c = 0; c < 3; ++c)
      r[B_ * nd.local + c] = u[B_ * nd.local + c] - g[c];
  }
}

void FluidProblem::jacobian(Vec U, Mat J) {
  add_jacobian(U, J);
  TF_PETSC(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
  TF_PETSC(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  // Dirichlet rows become identity rows (their residual is U - g); the pattern stays, so
  // the next assembly finds every entry where the inserter recorded it.
  TF_PETSC(MatSetOption(J, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE));
  TF_PETSC(MatZeroRows(J, static_cast<PetscInt>(dirichlet_rows_.size()), dirichlet_rows_.data(),
                       1.0, nullptr, nullptr));
}

void FluidProblem::attach_preconditioner(KSP ksp) {
  if (uses_schur_matrix(ksp))
    use_schur_matrix(ksp, schur_preconditioner());
}

Mat FluidProblem::schur_preconditioner() {
  if (!schur_)
    schur_ = std::make_unique<PressureSchur>(dmesh_);
  return schur_->matrix();
}

void FluidProblem::assemble_schur_preconditioner() {
  if (!schur_)
    return;
  const double c_u = scheme_.c_u(), c_a = scheme_.c_a(dt_);
  // The open faces (pressure_schur.hpp): the traction outlets, and with rigid walls every
  // face of the fluid, of which the triangles with a free velocity count (walls and inflows
  // are prescribed). In FSI the interface's velocity is the wall's, held by its inertia: only
  // the outlets are open there.
  std::vector<unsigned char> open(dmesh_.faces().size(), layout_.region < 0);
  for (const OutletData& o : outlets_)
    open[o.face_index] = 1;
  std::vector<PressureSchur::NodeTerm> open_terms;
  for (size_t i = 0; i < open.size(); ++i) {
    if (!open[i] || !fluid_face_[i])
      continue;
    for (const Tri& t : dmesh_.faces()[i].triangles) {
      if (dirichlet_[t[0]] == all_velocity && dirichlet_[t[1]] == all_velocity &&
          dirichlet_[t[2]] == all_velocity)
        continue; // a wall's or an inflow's
      double area;
      Vec3 n;
      bc::triangle_area_normal(x_[t[0]], x_[t[1]], x_[t[2]], area, n);
      const double term = schur_outlet_term(area, fluid_.density, c_u, c_a);
      for (Index l : t)
        open_terms.push_back({l, term});
    }
  }
  schur_->assemble(elements_, geometry_, stab_, fluid_, c_u, c_a, open_terms);
}

void FluidProblem::set_mesh_sensitivity(MeshSensitivity m) {
  sensitivity_ = std::move(m);
  interface_mask_.assign(geometry_.size(), 0);
  if (sensitivity_.follows.empty())
    return;
  const auto& tets = dmesh_.tets();
  for (size_t e : elements_)
    for (int a = 0; a < 4; ++a)
      if (sensitivity_.follows[tets[e][a]])
        interface_mask_[e] |= static_cast<std::uint8_t>(1u << a);
}

void FluidProblem::add_interface_motion(const Tet& t, unsigned mask, const fem::TetGeometry& geo,
                                        const FluidElementState& s, const Stabilization& stab,
                                        ElementMatrix& K) const {
  // dR/du_cj += dR/dx_cj dx_du + dR/dw_cj dw_du, by one forward difference per moving dof:
  // the node moved by 1e-7 of the element's size (sqrt of the round-off, so that the
  // difference's truncation and cancellation errors are both ~1e-7 relative).
  ElementVector R0, R1;
  navier_stokes_residual(geo, s, stab, fluid_, R0);
  const double du = 1e-7 * std::cbrt(std::abs(geo.volume)) / sensitivity_.dx_du;
  std::array<Vec3, 4> x{x_[t[0]], x_[t[1]], x_[t[2]], x_[t[3]]};
  FluidElementState moved = s;
  for (int c = 0; c < 4; ++c) {
    if (!((mask >> c) & 1u))
      continue;
    for (int j = 0; j < 3; ++j) {
      const double x0 = x[c][j], w0 = moved.w[c][j];
      x[c][j] += sensitivity_.dx_du * du;
      moved.w[c][j] += sensitivity_.dw_du * du;
      navier_stokes_residual(fem::tet_geometry(x), moved, stab, fluid_, R1);
      x[c][j] = x0;
      moved.w[c][j] = w0;
      for (int r = 0; r < 16; ++r)
        K[r][4 * c + j] += (R1[r] - R0[r]) / du;
    }
  }
}

void FluidProblem::add_jacobian(Vec U, Mat J) {
  stage(U);
  const double c_u = scheme_.c_u(), c_a = scheme_.c_a(dt_);
  const auto& tets = dmesh_.tets();
  FluidElementState s;
  ElementMatrix K;
  std::vector<double> Kx(B_ == 4 ? 0 : 16 * B_ * B_); // the element matrix in B_ slots
  inserter_.begin(J);
  for (size_t e : elements_) {
    gather(e, s);
    navier_stokes_jacobian(geometry_[e], s, stab_[e], fluid_, c_u, c_a, K);
    if (!interface_mask_.empty() && interface_mask_[e])
      add_interface_motion(tets[e], interface_mask_[e], geometry_[e], s, stab_[e], K);
    if (B_ == 4) {
      inserter_.add(e, &K[0][0]);
    } else {
      expand_element_matrix(&K[0][0], layout_, Kx.data());
      inserter_.add(e, Kx.data());
    }
  }
  inserter_.end();

  // Backflow term: d/du_dk of -beta rho int N_a (u.n)_- u_i = -beta rho c_u int N_a N_d
  // (n_k u_i + (u.n) delta_ik) where u.n < 0.
  const auto& x = x_;
  for (const OutletData& o : outlets_) {
    const double bf = o.spec.backflow_beta * fluid_.density;
    if (bf == 0.0)
      continue;
    for (const Tri& t : dmesh_.faces()[o.face_index].triangles) {
      double area;
      Vec3 n;
      bc::triangle_area_normal(x[t[0]], x[t[1]], x[t[2]], area, n);
      std::array<std::array<double, 9>, 9> Kb{};
      bool any = false;
      for (int q = 0; q < 3; ++q) {
        const int a0 = q, a1 = (q + 1) % 3;
        const Vec3 uq = 0.5 * (u_af_[t[a0]] + u_af_[t[a1]]);
        const double un = dot(uq, n);
        if (un >= 0.0)
          continue;
        any = true;
        for (int a : {a0, a1})
          for (int d : {a0, a1})
            for (int i = 0; i < 3; ++i)
              for (int k = 0; k < 3; ++k)
                Kb[3 * a + i][3 * d + k] -=
                    bf * c_u * area / 3.0 * 0.25 * (n[k] * uq[i] + (i == k ? un : 0.0));
      }
      if (!any)
        continue;
      std::array<PetscInt, 9> dofs;
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c)
          dofs[3 * a + c] = dofs_.global_dof(t[a], c);
      TF_PETSC(MatSetValues(J, 9, dofs.data(), 9, dofs.data(), &Kb[0][0], ADD_VALUES));
    }
  }
}

void FluidProblem::add_coupled_outlets(Vec x, Vec y) const {
  for (const OutletData& o : outlets_) {
    if (o.law.resistance == 0.0)
      continue;
    PetscScalar vx;
    TF_PETSC(VecDot(o.v, x, &vx));
    TF_PETSC(VecAXPY(y, o.law.resistance * scheme_.c_u() * vx, o.v));
  }
}

void FluidProblem::update_acceleration(Vec U_next, Vec U_n, Vec Udot) const {
  const double gamma = scheme_.gamma;
  fem::ReadArray u(U_next), un(U_n);
  fem::WriteArray ud(Udot);
  for (Index l = 0; l < dmesh_.num_owned(); ++l)
    for (int c = 0; c < 3; ++c) {
      const PetscInt i = B_ * l + c;
      ud[i] = (u[i] - un[i]) / (gamma * dt_) - (1.0 - gamma) / gamma * ud[i];
    }
}

std::vector<FaceMeasure> FluidProblem::measure_faces(Vec U) const {
  dofs_.global_to_local(U, U_loc_);
  fem::ReadArray u(U_loc_);
  const auto& x = x_;
  constexpr int per_face = 4; // flow, pressure, area, reversed
  std::vector<double> sums;
  for (const fem::LocalFace& f : dmesh_.faces()) {
    double area_sum = 0.0, flow = 0.0, pressure = 0.0, reversed = 0.0;
    for (const Tri& t : f.triangles) {
      double area;
      Vec3 n;
      bc::triangle_area_normal(x[t[0]], x[t[1]], x[t[2]], area, n);
      area_sum += area;
      for (Index l : t) {
        const double un = u[B_ * l] * n[0] + u[B_ * l + 1] * n[1] + u[B_ * l + 2] * n[2];
        flow += area / 3.0 * un;
        reversed += area / 3.0 * std::min(un, 0.0);
        pressure += area / 3.0 * u[B_ * l + P_];
      }
    }
    sums.insert(sums.end(), {flow, pressure, area_sum, reversed});
  }
  MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_DOUBLE, MPI_SUM,
                dmesh_.comm());
  std::vector<FaceMeasure> out;
  for (size_t i = 0; i < dmesh_.faces().size(); ++i) {
    if (!fluid_face_[i]) // a face of the wall only (FSI): no flow to measure
      continue;
    const double* s = &sums[per_face * i];
    out.push_back({dmesh_.faces()[i].name, s[0], s[1] / s[2], s[2], s[3]});
  }
  return out;
}

} // namespace tearflow::physics
