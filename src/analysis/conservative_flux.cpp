#include "analysis/conservative_flux.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>

#include "core/error.hpp"
#include "fem/p1_tet.hpp"

namespace tearflow::analysis {

namespace {

Vec3 tuple3(vtkDataArray* a, vtkIdType i) {
  if (a == nullptr)
    return {};
  double v[3];
  a->GetTuple(i, v);
  return {v[0], v[1], v[2]};
}

/// (a_after - a_before) / dt of a 3-component point field, null when the frames lack it.
vtkSmartPointer<vtkDoubleArray> difference(vtkUnstructuredGrid* before, vtkUnstructuredGrid* after,
                                           const char* name, double dt) {
  vtkDataArray* a = before->GetPointData()->GetArray(name);
  vtkDataArray* b = after->GetPointData()->GetArray(name);
  if (a == nullptr || b == nullptr || dt <= 0)
    return nullptr;
  if (a->GetNumberOfTuples() != b->GetNumberOfTuples())
    input_error("frames of different meshes ({} and {} nodes): the analysis needs one mesh",
                a->GetNumberOfTuples(), b->GetNumberOfTuples());
  auto out = vtkSmartPointer<vtkDoubleArray>::New();
  out->SetNumberOfComponents(3);
  out->SetNumberOfTuples(a->GetNumberOfTuples());
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i) {
    const Vec3 rate = (1.0 / dt) * (tuple3(b, i) - tuple3(a, i));
    out->SetTuple(i, rate.data());
  }
  return out;
}

ContinuityState sized(vtkIdType n) {
  const auto m = static_cast<std::size_t>(n);
  ContinuityState s;
  s.x.resize(m);
  s.x_lagged.resize(m);
  s.u.resize(m);
  s.udot.resize(m);
  s.w.resize(m);
  s.lagged.resize(m);
  s.p.resize(m);
  return s;
}

/// sigma_h as the solver reconstructs it (physics/navier_stokes_kernel.hpp): the lumped L2
/// projection of 2 mu eps(v) over the grid's tetrahedra on the mesh s.x_lagged, v the
/// velocity the solver took (`predictor`). Nothing unless the run has the correction.
void reconstruct_viscous_flux(vtkUnstructuredGrid* grid, const std::vector<Vec3>& predictor,
                              const ContinuityForm& form, ContinuityState& s) {
  if (!form.fluid.stabilization.viscous_correction)
    return;
  const std::size_t n = s.x.size();
  std::vector<physics::SymTensor> sum(n, physics::SymTensor{});
  std::vector<double> volume(n, 0.0);
  for (vtkIdType cell = 0; cell < grid->GetNumberOfCells(); ++cell) {
    vtkIdType count = 0;
    const vtkIdType* ids = nullptr;
    grid->GetCellPoints(cell, count, ids);
    if (count != 4)
      continue;
    std::array<Vec3, 4> x, v;
    for (int a = 0; a < 4; ++a) {
      x[a] = s.x_lagged[static_cast<std::size_t>(ids[a])];
      v[a] = predictor[static_cast<std::size_t>(ids[a])];
    }
    const fem::TetGeometry geo = fem::tet_geometry(x);
    const physics::SymTensor sigma = physics::viscous_flux(geo, v, form.fluid.viscosity);
    const double share = 0.25 * std::abs(geo.volume);
    for (int a = 0; a < 4; ++a) {
      const auto k = static_cast<std::size_t>(ids[a]);
      for (int c = 0; c < 6; ++c)
        sum[k][c] += share * sigma[c];
      volume[k] += share;
    }
  }
  for (std::size_t k = 0; k < n; ++k)
    for (int c = 0; c < 6; ++c)
      sum[k][c] = volume[k] > 0 ? sum[k][c] / volume[k] : 0.0;
  s.viscous_flux = std::move(sum);
}

} // namespace

FrameDifferences frame_differences(vtkUnstructuredGrid* before, double t_before,
                                   vtkUnstructuredGrid* after, double t_after) {
  const double dt = t_after - t_before;
  return {difference(before, after, "velocity", dt), difference(before, after, "displacement", dt)};
}

WallTriangles wall_triangles(vtkUnstructuredGrid* grid) {
  WallTriangles out;
  vtkDataArray* on_wall = grid->GetPointData()->GetArray(kOnWallArray);
  if (on_wall == nullptr)
    return out;
  const auto marked = [&](vtkIdType id) { return on_wall->GetTuple1(id) > 0.5; };
  // A face is on the boundary when one tetrahedron holds it; key: its sorted nodes.
  std::map<std::array<vtkIdType, 3>, std::pair<int, std::array<vtkIdType, 4>>> faces;
  for (vtkIdType cell = 0; cell < grid->GetNumberOfCells(); ++cell) {
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    grid->GetCellPoints(cell, n, ids);
    if (n != 4)
      continue;
    for (int opposite = 0; opposite < 4; ++opposite) {
      std::array<vtkIdType, 4> f{};
      int m = 0;
      for (int a = 0; a < 4; ++a)
        if (a != opposite)
          f[m++] = ids[a];
      f[3] = ids[opposite];
      if (!(marked(f[0]) && marked(f[1]) && marked(f[2])))
        continue;
      std::array<vtkIdType, 3> key{f[0], f[1], f[2]};
      std::sort(key.begin(), key.end());
      auto [it, inserted] = faces.try_emplace(key, 0, f);
      ++it->second.first;
    }
  }
  for (const auto& [key, entry] : faces) {
    if (entry.first != 1)
      continue;
    const auto& f = entry.second;
    std::array<Vec3, 4> x;
    for (int a = 0; a < 4; ++a)
      grid->GetPoint(f[a], x[a].data());
    const bool outward = dot(cross(x[1] - x[0], x[2] - x[0]), x[3] - x[0]) < 0;
    out.push_back(outward ? std::array<vtkIdType, 3>{f[0], f[1], f[2]}
                          : std::array<vtkIdType, 3>{f[0], f[2], f[1]});
  }
  return out;
}

namespace {

/// The pressure unknown as the step posed it: `stage_pressure` where the frame has it (the
/// `pressure` of such a frame is at the frame's time, run/flow_model.hpp), else `pressure`.
vtkDataArray* stage_pressure(vtkUnstructuredGrid* frame) {
  vtkDataArray* stage = frame->GetPointData()->GetArray(kStagePressure);
  return stage != nullptr ? stage : frame->GetPointData()->GetArray("pressure");
}

} // namespace

bool has_acceleration(vtkUnstructuredGrid* frame) {
  vtkDataArray* a = frame->GetPointData()->GetArray(kAcceleration);
  return a != nullptr && a->GetNumberOfComponents() == 3;
}

ContinuityState step_stage(vtkUnstructuredGrid* before, vtkUnstructuredGrid* after,
                           const ContinuityForm& form, std::shared_ptr<const WallTriangles> wall) {
  const vtkIdType n = after->GetNumberOfPoints();
  if (before->GetNumberOfPoints() != n || before->GetNumberOfCells() != after->GetNumberOfCells())
    input_error("frames of different meshes ({} and {} nodes): the analysis needs one mesh",
                before->GetNumberOfPoints(), n);
  const auto [am, af, gamma] = form.scheme;
  const double dt = form.time_step;
  vtkDataArray* u0 = before->GetPointData()->GetArray("velocity");
  vtkDataArray* u1 = after->GetPointData()->GetArray("velocity");
  vtkDataArray* a0 = before->GetPointData()->GetArray(kAcceleration);
  vtkDataArray* a1 = after->GetPointData()->GetArray(kAcceleration);
  vtkDataArray* p1 = stage_pressure(after);
  ContinuityState s = sized(n);
  s.time_step = dt;
  s.exact = true;
  for (vtkIdType i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    Vec3 x0, x1;
    before->GetPoint(i, x0.data());
    after->GetPoint(i, x1.data());
    const Vec3 un = tuple3(u0, i);
    s.x[k] = x0 + af * (x1 - x0); // the mesh at t_n + alpha_f dt, moving at w
    s.w[k] = (1.0 / dt) * (x1 - x0);
    s.x_lagged[k] = x0; // tau_M on the mesh at t_n with u_n (w = 0 there)
    s.lagged[k] = un;
    s.u[k] = un + af * (tuple3(u1, i) - un);
    s.udot[k] = tuple3(a0, i) + am * (tuple3(a1, i) - tuple3(a0, i));
    s.p[k] = p1->GetTuple1(i);
  }
  std::vector<Vec3> predictor(static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
    predictor[static_cast<std::size_t>(i)] = tuple3(u0, i) + af * dt * tuple3(a0, i);
  reconstruct_viscous_flux(after, predictor, form, s);
  s.wall = std::move(wall);
  return s;
}

ContinuityState frame_state(vtkUnstructuredGrid* frame, const FrameRates& rates,
                            const ContinuityForm& form, std::shared_ptr<const WallTriangles> wall) {
  const vtkIdType n = frame->GetNumberOfPoints();
  vtkDataArray* velocity = frame->GetPointData()->GetArray("velocity");
  vtkDataArray* pressure = stage_pressure(frame);
  vtkDataArray* udot =
      has_acceleration(frame) ? frame->GetPointData()->GetArray(kAcceleration) : rates.acceleration;
  ContinuityState s = sized(n);
  s.time_step = form.time_step;
  for (vtkIdType i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    frame->GetPoint(i, s.x[k].data());
    s.x_lagged[k] = s.x[k];
    s.u[k] = tuple3(velocity, i);
    s.udot[k] = tuple3(udot, i);
    s.w[k] = tuple3(rates.mesh_velocity, i);
    s.lagged[k] = s.u[k] - form.time_step * s.udot[k] - s.w[k]; // ~ u_n - w
    s.p[k] = pressure->GetTuple1(i);
  }
  // u_n + alpha_f dt udot ~ u - (1 - alpha_f) dt udot
  std::vector<Vec3> predictor(static_cast<std::size_t>(n));
  for (std::size_t k = 0; k < predictor.size(); ++k)
    predictor[k] = s.u[k] - (1.0 - form.scheme.alpha_f) * form.time_step * s.udot[k];
  reconstruct_viscous_flux(frame, predictor, form, s);
  s.wall = std::move(wall);
  return s;
}

PlaneFlux conservative_fluxes(vtkUnstructuredGrid* grid, const ContinuityState& state,
                              const Vec3& origin, const Vec3& normal, const RegionOf& region_of,
                              vtkIdType regions, const ContinuityForm& form) {
  PlaneFlux out;
  const auto region_count = static_cast<std::size_t>(std::max<vtkIdType>(regions, 0));
  out.regions.assign(region_count, 0.0);
  // The downstream parts: far-side nodes joined by the tetrahedra's edges (union-find).
  std::vector<vtkIdType> parent(state.x.size());
  for (std::size_t i = 0; i < parent.size(); ++i)
    parent[i] = static_cast<vtkIdType>(i);
  const auto root = [&](vtkIdType i) {
    while (parent[static_cast<std::size_t>(i)] != i)
      i = parent[static_cast<std::size_t>(i)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
    return i;
  };
  std::vector<vtkIdType> region_node(region_count, -1); // a far-side node of each region's layer
  const double rho = form.fluid.density;
  const auto downstream_of = [&](vtkIdType id) {
    return dot(state.x[static_cast<std::size_t>(id)] - origin, normal) > 0;
  };
  std::array<Vec3, 4> x, x_lagged;
  std::array<double, 4> d;
  for (vtkIdType cell = 0; cell < grid->GetNumberOfCells(); ++cell) {
    if (grid->GetCellType(cell) != VTK_TETRA)
      input_error("the conservative flux needs linear tetrahedra; cell {} is of VTK type {}", cell,
                  grid->GetCellType(cell));
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    grid->GetCellPoints(cell, n, ids);
    int downstream = 0;
    for (int a = 0; a < 4; ++a) {
      const auto k = static_cast<std::size_t>(ids[a]);
      x[a] = state.x[k];
      x_lagged[a] = state.x_lagged[k];
      d[a] = dot(x[a] - origin, normal);
      downstream += d[a] > 0 ? 1 : 0;
    }
    vtkIdType first_far = -1;
    for (int a = 0; a < 4; ++a)
      if (d[a] > 0) {
        if (first_far < 0)
          first_far = ids[a];
        else
          parent[static_cast<std::size_t>(root(ids[a]))] = root(first_far);
      }
    if (downstream == 0 || downstream == 4)
      continue; // psi is constant here: no share of the layer
    // A point of the section inside this tetrahedron (the mean of its cut edges' crossings)
    // says which lumen the tetrahedron's share belongs to.
    Vec3 on_plane{};
    int crossings = 0;
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        if ((d[a] > 0) != (d[b] > 0)) {
          on_plane = on_plane + (x[a] + (d[a] / (d[a] - d[b])) * (x[b] - x[a]));
          ++crossings;
        }
    const vtkIdType region = region_of((1.0 / crossings) * on_plane);
    if (region < 0 || region >= regions)
      continue;
    if (region_node[static_cast<std::size_t>(region)] < 0)
      region_node[static_cast<std::size_t>(region)] = first_far;

    // The element's share of F: grad psi . (u - tau_M / rho r_M), with the solver's kernel
    // for r_M (u.grad u on the convective velocity u - w, grad p, du/dt) and tau_M.
    const fem::TetGeometry geo = fem::tet_geometry(x);
    physics::FluidElementState s;
    Vec3 lagged{};
    for (int a = 0; a < 4; ++a) {
      const auto k = static_cast<std::size_t>(ids[a]);
      s.u[a] = state.u[k];
      s.udot[a] = state.udot[k];
      s.w[a] = state.w[k];
      s.p[a] = state.p[k];
      lagged = lagged + 0.25 * state.lagged[k];
    }
    if (!state.viscous_flux.empty())
      s.viscous =
          physics::flux_divergence(geo, {state.viscous_flux[static_cast<std::size_t>(ids[0])],
                                         state.viscous_flux[static_cast<std::size_t>(ids[1])],
                                         state.viscous_flux[static_cast<std::size_t>(ids[2])],
                                         state.viscous_flux[static_cast<std::size_t>(ids[3])]});
    const physics::FluidElementFields f = physics::element_fields(geo, s, form.fluid);
    const physics::Stabilization stab =
        physics::stabilization(fem::tet_geometry(x_lagged), lagged, form.fluid, state.time_step);
    Vec3 grad_psi{}, u_mean{}, r_mean{};
    for (int a = 0; a < 4; ++a) {
      if (d[a] > 0)
        grad_psi = grad_psi + geo.grad[a];
      u_mean = u_mean + 0.25 * s.u[a];
      r_mean = r_mean + 0.25 * f.r[a];
    }
    const double volume = std::abs(geo.volume);
    out.regions[static_cast<std::size_t>(region)] +=
        volume * (dot(grad_psi, u_mean) - stab.tau_m / rho * dot(grad_psi, r_mean));
  }
  // W = int_wall psi u.n dA, exact for the P1 psi and u: the mass matrix A (1 + delta_ab) / 12.
  std::map<vtkIdType, double> wall; // per downstream part (its root)
  static const WallTriangles none;
  for (const auto& t : state.wall ? *state.wall : none) {
    const std::array<std::size_t, 3> k{static_cast<std::size_t>(t[0]),
                                       static_cast<std::size_t>(t[1]),
                                       static_cast<std::size_t>(t[2])};
    const Vec3 area_normal =
        0.5 * cross(state.x[k[1]] - state.x[k[0]], state.x[k[2]] - state.x[k[0]]);
    for (int a = 0; a < 3; ++a) {
      if (!downstream_of(t[a]))
        continue;
      for (int b = 0; b < 3; ++b)
        wall[root(t[a])] += (a == b ? 2.0 : 1.0) / 12.0 * dot(state.u[k[b]], area_normal);
    }
  }
  out.wall.assign(region_count, 0.0);
  out.part.assign(region_count, -1);
  for (std::size_t r = 0; r < region_count; ++r)
    if (region_node[r] >= 0) {
      out.part[r] = root(region_node[r]);
      const auto it = wall.find(out.part[r]);
      out.wall[r] = it == wall.end() ? 0.0 : it->second;
    }
  return out;
}

} // namespace tearflow::analysis
