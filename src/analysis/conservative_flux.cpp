#include "analysis/conservative_flux.hpp"

#include <cmath>

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

} // namespace

FrameDifferences frame_differences(vtkUnstructuredGrid* before, double t_before,
                                   vtkUnstructuredGrid* after, double t_after) {
  const double dt = t_after - t_before;
  return {difference(before, after, "velocity", dt), difference(before, after, "displacement", dt)};
}

std::vector<double> conservative_fluxes(vtkUnstructuredGrid* grid, const Vec3& origin,
                                        const Vec3& normal, const RegionOf& region_of,
                                        vtkIdType regions, const FrameRates& rates,
                                        const ContinuityForm& form) {
  vtkDataArray* velocity = grid->GetPointData()->GetArray("velocity");
  vtkDataArray* pressure = grid->GetPointData()->GetArray("pressure");
  std::vector<double> flux(static_cast<std::size_t>(std::max<vtkIdType>(regions, 0)), 0.0);
  const double dt = form.time_step, rho = form.fluid.density;
  std::array<Vec3, 4> x;
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
      grid->GetPoint(ids[a], x[a].data());
      d[a] = dot(x[a] - origin, normal);
      downstream += d[a] > 0 ? 1 : 0;
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

    // The element's share of F: grad psi . (u - tau_M / rho r_M), with the solver's kernel
    // for r_M and tau_M (u.grad u, grad p and du/dt, on the convective velocity c = u - w).
    const fem::TetGeometry geo = fem::tet_geometry(x);
    physics::FluidElementState s;
    Vec3 lagged{};
    for (int a = 0; a < 4; ++a) {
      s.u[a] = tuple3(velocity, ids[a]);
      s.udot[a] = tuple3(rates.acceleration, ids[a]);
      s.w[a] = tuple3(rates.mesh_velocity, ids[a]);
      s.p[a] = pressure->GetTuple1(ids[a]);
      // tau_M takes the previous step's convective velocity (fluid_problem.cpp).
      lagged = lagged + 0.25 * (s.u[a] - dt * s.udot[a] - s.w[a]);
    }
    const physics::FluidElementFields f = physics::element_fields(geo, s, form.fluid);
    const physics::Stabilization stab = physics::stabilization(geo, lagged, form.fluid, dt);
    Vec3 grad_psi{}, u_mean{}, r_mean{};
    for (int a = 0; a < 4; ++a) {
      if (d[a] > 0)
        grad_psi = grad_psi + geo.grad[a];
      u_mean = u_mean + 0.25 * s.u[a];
      r_mean = r_mean + 0.25 * f.r[a];
    }
    const double volume = std::abs(geo.volume);
    flux[static_cast<std::size_t>(region)] +=
        volume * (dot(grad_psi, u_mean) - stab.tau_m / rho * dot(grad_psi, r_mean));
  }
  return flux;
}

} // namespace tearflow::analysis
