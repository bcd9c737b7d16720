#!/usr/bin/python3
"""Steady flow in a rigid pipe the size of the dissection's true lumen, at its Reynolds number
and the study's step: the 3D solver's pressure loss against Hagen-Poiseuille's, per element
size, on the uniform tet mesh and with boundary layers; prints JSON.

usage: bench/pipe_pressure_drop.py [--sizes-mm 2.5 1.8 1.3 0.9] [--layers 2 --first-layer 0.3
       --growth 1.3] [--ranks 2] [--keep DIR] [--case-extra "viscous_correction: false"]
       [--max-uniform-loss R] [--max-layered-loss R]

With --max-*-loss the exit status is 1 when a run's loss of mechanical energy
(`energy_ratio_to_poiseuille`) exceeds R times Poiseuille's (CTest's reduced form:
tests/CMakeLists.txt, bench.pipe_pressure_drop.reduced).

The pipe: radius 4.3 mm (58 mm^2, the TL at stations 3-5), length 80 mm, 30 mL/s (the TL's
peak-systolic flow in OR; Re = 1160), parabolic inflow, zero outlet pressure, dt 10 ms (the
study's), 30 steps to the steady state. The mesh: Gmsh's (the `gmsh` program) OpenCASCADE
cylinder at the element size, and the same mesh with `tearflow geometry layers` when --layers
is given; each row has both. Measured over z = 20-60 mm against Hagen-Poiseuille's 37.5 Pa:
- `ratio_to_poiseuille`: the static pressure drop on the axis;
- `energy_ratio_to_poiseuille`: the loss of mechanical energy, the flux of p + rho |u|^2 / 2
  through the two cross-sections divided by Q. It equals the static drop in developed flow;
  where the discrete profile still develops from the inflow's parabola (it does over the
  whole pipe at Re 1160 when the mesh's own profile differs from it), the static drop also
  holds the kinetic energy the profile gains or gives up, the energy loss does not;
- `resolved_dissipation_share`: the computed velocity field's viscous dissipation
  int 2 mu eps:eps dV over the span as a share of that energy loss; the rest is the
  stabilized scheme's own dissipation (docs/performance.md, "The P1 scheme's loss in a
  narrow lumen").
Needs VTK's Python (Debian python3-vtk9) and numpy.
"""
import argparse, json, math, os, shutil, subprocess, sys, tempfile

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "tearflow")
R, LENGTH, Q, MU, RHO = 4.3e-3, 0.08, 30e-6, 0.0042, 1100.0
Z0, Z1 = 0.25 * LENGTH, 0.75 * LENGTH

GEO = """SetFactory("OpenCASCADE");
Cylinder(1) = {{0, 0, 0, 0, 0, {l}, {r}}};
Physical Volume("fluid") = {{1}};
Physical Surface("wall") = {{1}};
Physical Surface("inlet") = {{3}};
Physical Surface("outlet") = {{2}};
Mesh.MeshSizeMin = {h};
Mesh.MeshSizeMax = {h};
Mesh.Algorithm = 6;
Mesh.Algorithm3D = 1;
Mesh.MshFileVersion = 2.2;
"""

CASE = """name: pipe-{h}
mesh: {{file: {mesh}, units: mm}}
fluid: {{density: {rho}, viscosity: {mu}{extra}}}
time: {{step: 0.01, end: 0.3, spectral_radius: 0.5}}
boundary_conditions:
  - {{face: wall, type: no_slip}}
  - face: inlet
    type: inflow
    flow: {{times: [0, 0.25, 0.5, 0.75], values: [{q}, {q}, {q}, {q}], units: mL/s, period: 1.0}}
    profile: parabolic
  - {{face: outlet, type: pressure, pressure: 0}}
output: {{directory: {out}, every: 30}}
"""


def section_integrals(grid, z):
    """Area, flux of u_z, and flux of (p + rho |u|^2 / 2) u_z through the section z."""
    plane = vtk.vtkPlane()
    plane.SetOrigin(0, 0, z)
    plane.SetNormal(0, 0, 1)
    cut = vtk.vtkCutter()
    cut.SetInputData(grid)
    cut.SetCutFunction(plane)
    cut.Update()
    section = cut.GetOutput()
    u = vtk_to_numpy(section.GetPointData().GetArray("velocity"))
    p = vtk_to_numpy(section.GetPointData().GetArray("pressure"))
    energy = vtk.vtkDoubleArray()
    energy.SetName("energy_flux")
    for value in (p + 0.5 * RHO * (u * u).sum(axis=1)) * u[:, 2]:
        energy.InsertNextValue(value)
    section.GetPointData().AddArray(energy)
    integrate = vtk.vtkIntegrateAttributes()
    integrate.SetInputData(section)
    integrate.Update()
    out = integrate.GetOutput()
    area = out.GetCellData().GetArray("Area").GetValue(0)
    flow = out.GetPointData().GetArray("velocity").GetTuple3(0)[2]
    return area, flow, out.GetPointData().GetArray("energy_flux").GetValue(0)


def measure(vtu):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(vtu)
    r.Update()
    g = r.GetOutput()
    pts = vtk.vtkPoints()
    for z in (Z0, Z1):
        pts.InsertNextPoint(0.0, 0.0, z)
    probe_points = vtk.vtkPolyData()
    probe_points.SetPoints(pts)
    probe = vtk.vtkProbeFilter()
    probe.SetInputData(probe_points)
    probe.SetSourceData(g)
    probe.Update()
    p = vtk_to_numpy(probe.GetOutput().GetPointData().GetArray("pressure"))
    drop = float(p[0] - p[1])
    (_, q0, e0), (_, _, e1) = section_integrals(g, Z0), section_integrals(g, Z1)
    energy_drop = (e0 - e1) / q0
    # Resolved dissipation over the span: per tet, the P1 velocity gradient is constant.
    x = vtk_to_numpy(g.GetPoints().GetData())
    u = vtk_to_numpy(g.GetPointData().GetArray("velocity"))
    tets = vtk_to_numpy(g.GetCells().GetConnectivityArray()).reshape(-1, 4)
    xt = x[tets]
    edges = xt[:, 1:] - xt[:, :1]
    grad = np.linalg.solve(edges, u[tets][:, 1:] - u[tets][:, :1])  # grad[i, j] = du_j / dx_i
    volume = np.abs(np.linalg.det(edges)) / 6.0
    eps = 0.5 * (grad + np.transpose(grad, (0, 2, 1)))
    centre_z = xt[:, :, 2].mean(axis=1)
    span = (centre_z > Z0) & (centre_z < Z1)
    dissipation = float((2.0 * MU * np.einsum("nij,nij->n", eps, eps) * volume)[span].sum())
    return drop, energy_drop, dissipation, len(tets)


def run(mesh, work, name, ranks, extra):
    out = os.path.join(work, name)
    case = os.path.join(work, name + ".yaml")
    with open(case, "w") as f:
        f.write(CASE.format(h=name, mesh=mesh, rho=RHO, mu=MU, q=Q * 1e6, out=out, extra=extra))
    cmd = [BIN, "run", "-q", case]
    if ranks > 1:
        cmd = ["mpirun", "-n", str(ranks)] + cmd
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    drop, energy_drop, dissipation, tets = measure(os.path.join(out, "flow_000030.vtu"))
    exact = 8.0 * MU * Q / (math.pi * R**4) * (Z1 - Z0)
    return {"tets": tets, "pressure_drop_Pa": round(drop, 2),
            "ratio_to_poiseuille": round(drop / exact, 3),
            "energy_ratio_to_poiseuille": round(energy_drop / exact, 3),
            "resolved_dissipation_share": round(dissipation / (Q * energy_drop), 3)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes-mm", type=float, nargs="+", default=[2.5, 1.8, 1.3, 0.9])
    ap.add_argument("--layers", type=int, default=0, help="boundary layers (0: none)")
    ap.add_argument("--first-layer", type=float, default=0.3, help="mm")
    ap.add_argument("--growth", type=float, default=1.3)
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--keep", help="keep the runs in this directory")
    ap.add_argument("--case-extra", default="", help="more fluid keys, e.g. 'grad_div_scale: 1'")
    ap.add_argument("--max-uniform-loss", type=float, help="fail above this energy ratio (uniform)")
    ap.add_argument("--max-layered-loss", type=float, help="fail above this energy ratio (layers)")
    a = ap.parse_args()
    work = a.keep or tempfile.mkdtemp(prefix="tearflow-pipe-drop-")
    os.makedirs(work, exist_ok=True)
    extra = ", " + a.case_extra if a.case_extra else ""
    rows = []
    for h in a.sizes_mm:
        geo = os.path.join(work, f"pipe-{h}.geo")
        with open(geo, "w") as f:
            f.write(GEO.format(r=R * 1e3, l=LENGTH * 1e3, h=h))
        mesh = os.path.join(work, f"pipe-{h}.msh")
        subprocess.run(["gmsh", "-3", geo, "-o", mesh], check=True, stdout=subprocess.DEVNULL)
        row = {"element_size_mm": h, "elements_across_diameter": round(2 * R / (h * 1e-3), 1),
               "uniform": run(mesh, work, f"h{h}", a.ranks, extra)}
        if a.layers > 0:
            layered = os.path.join(work, f"pipe-{h}-layers")
            subprocess.run([BIN, "geometry", "layers", mesh, "-o", layered, "--layers",
                            str(a.layers), "--first-layer", str(a.first_layer), "--growth",
                            str(a.growth)], check=True, stdout=subprocess.DEVNULL)
            row["layers"] = run(os.path.join(layered, "mesh.msh"), work, f"h{h}-layers", a.ranks,
                                extra)
        rows.append(row)
    if not a.keep:
        shutil.rmtree(work)
    print(json.dumps({"pipe": {"radius_m": R, "length_m": LENGTH, "flow_m3_per_s": Q,
                               "reynolds": round(RHO * (Q / (math.pi * R * R)) * 2 * R / MU),
                               "step_s": 0.01, "span_m": [Z0, Z1],
                               "poiseuille_Pa": round(8.0 * MU * Q / (math.pi * R**4) * (Z1 - Z0), 2),
                               "layers": {"count": a.layers, "first_mm": a.first_layer,
                                          "growth": a.growth} if a.layers else None,
                               "case_extra": a.case_extra or None},
                      "runs": rows}, indent=1))
    failed = []
    for row in rows:
        for kind, bound in (("uniform", a.max_uniform_loss), ("layers", a.max_layered_loss)):
            loss = row.get(kind, {}).get("energy_ratio_to_poiseuille")
            if bound is not None and loss is not None and loss > bound:
                failed.append(f"{row['element_size_mm']} mm, {kind}: {loss} > {bound}")
    if failed:
        print("energy loss above its bound (x Poiseuille): " + "; ".join(failed), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
