#!/usr/bin/python3
"""Steady flow in a rigid pipe the size of the dissection's true lumen, at its Reynolds number
and the study's step: the 3D solver's pressure drop against Hagen-Poiseuille's, per element size;
prints JSON.

usage: bench/pipe_pressure_drop.py [--sizes-mm 2.5 1.8 1.3 0.9] [--ranks 2] [--keep DIR]

The pipe: radius 4.3 mm (58 mm^2, the TL at stations 3-5), length 80 mm, 30 mL/s (the TL's
peak-systolic flow in OR; Re = 1160), parabolic inflow, zero outlet pressure, dt 10 ms (the
study's), 30 steps to the steady state. Measured on the axis between z = 20 and 60 mm (the
inlet's profile is already Poiseuille's, so the flow is developed there), with the resolved
viscous dissipation int 2 mu eps:eps dV over the same span against Q dp: the share of the drop
that the computed velocity field's viscosity accounts for. The rest is the stabilized scheme's
own dissipation (docs/rom.md, "The 3D runs' losses"). Needs VTK's Python (Debian python3-vtk9).
"""
import argparse, json, math, os, shutil, subprocess, sys, tempfile

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "tearflow")
R, LENGTH, Q, MU, RHO = 4.3e-3, 0.08, 30e-6, 0.0042, 1100.0

CASE = """name: pipe-{h}
mesh:
  pipe: {{radius: {r}, length: {l}, element_size: {size}}}
fluid: {{density: {rho}, viscosity: {mu}}}
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


def measure(vtu):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(vtu)
    r.Update()
    g = r.GetOutput()
    pts = vtk.vtkPoints()
    for z in (0.25 * LENGTH, 0.75 * LENGTH):
        pts.InsertNextPoint(0.0, 0.0, z)
    probe_points = vtk.vtkPolyData()
    probe_points.SetPoints(pts)
    probe = vtk.vtkProbeFilter()
    probe.SetInputData(probe_points)
    probe.SetSourceData(g)
    probe.Update()
    p = vtk_to_numpy(probe.GetOutput().GetPointData().GetArray("pressure"))
    drop = float(p[0] - p[1])
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
    span = (centre_z > 0.25 * LENGTH) & (centre_z < 0.75 * LENGTH)
    dissipation = float((2.0 * MU * np.einsum("nij,nij->n", eps, eps) * volume)[span].sum())
    return drop, dissipation, len(tets)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes-mm", type=float, nargs="+", default=[2.5, 1.8, 1.3, 0.9])
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--keep", help="keep the runs in this directory")
    a = ap.parse_args()
    work = a.keep or tempfile.mkdtemp(prefix="tearflow-pipe-drop-")
    os.makedirs(work, exist_ok=True)
    exact = 8.0 * MU * Q / (math.pi * R**4) * 0.5 * LENGTH
    rows = []
    for h in a.sizes_mm:
        out = os.path.join(work, f"h{h}")
        case = os.path.join(work, f"pipe-{h}.yaml")
        with open(case, "w") as f:
            f.write(CASE.format(h=h, r=R, l=LENGTH, size=h * 1e-3, rho=RHO, mu=MU, q=Q * 1e6, out=out))
        cmd = [BIN, "run", "-q", case]
        if a.ranks > 1:
            cmd = ["mpirun", "-n", str(a.ranks)] + cmd
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        drop, dissipation, tets = measure(os.path.join(out, "flow_000030.vtu"))
        rows.append({"element_size_mm": h, "tets": tets,
                     "elements_across_diameter": round(2 * R / (h * 1e-3), 1),
                     "pressure_drop_Pa": round(drop, 2), "poiseuille_Pa": round(exact, 2),
                     "ratio_to_poiseuille": round(drop / exact, 2),
                     "resolved_dissipation_share": round(dissipation / (Q * drop), 3)})
    if not a.keep:
        shutil.rmtree(work)
    print(json.dumps({"pipe": {"radius_m": R, "length_m": LENGTH, "flow_m3_per_s": Q,
                               "reynolds": round(RHO * (Q / (math.pi * R * R)) * 2 * R / MU),
                               "step_s": 0.01},
                      "runs": rows}, indent=1))


if __name__ == "__main__":
    sys.exit(main())
