#!/usr/bin/env python3
"""Time per step and per Newton iteration of the solid (vessel wall) solver; prints JSON.

usage: bench/solid_step.py [--steps N] [--ranks 1 2] [--cases tube100k] [--petsc '...']
Case tube100k: a straight tube wall like the study's aorta (inner radius 12 mm, wall 2 mm,
length 87 mm), structured: 2 x 96 x 87 hexahedra cut into 6 tets each (100,224 tets),
written as a Gmsh 2.2 file. Neo-Hookean, E 1.2 MPa, nu 0.49, 1450 kg/m^3; both end rings
fixed; inner follower pressure 10 kPa (step at t = 0); outer tissue support k_s 18 MN/m^3,
c_s 30 kN s/m^3 (the study's); dt 1 ms, rho_inf 0.5. Reports per rank count: mean seconds
per step, per Newton iteration, assembly seconds per step, Newton and KSP iterations per
step, peak resident memory (max over ranks). The first step is excluded (start-up).
"""
import argparse, json, math, os, platform, tempfile, time

from run_progress import run_case


CASE = """name: {name}
mesh: {{file: {mesh}}}
solid:
  model: neo_hookean
  density: 1450
  youngs_modulus: 1.2e6
  poisson_ratio: 0.49
  boundary_conditions:
    - {{face: z0, type: fixed}}
    - {{face: z1, type: fixed}}
    - {{face: inner, type: pressure, pressure: 1.0e4}}
    - {{face: outer, type: robin, stiffness: 18.0e6, damping: 30.0e3}}
time: {{step: 0.001, steps: {steps}, spectral_radius: 0.5}}
newton: {{max_iterations: 10, rtol: 1.0e-6, atol: 1.0e-12}}
{petsc}output: {{every: 0}}
"""

def write_tube(path, a=0.012, b=0.014, length=0.087, nr=2, nt=96, nz=87):
    """Structured tube wall, Kuhn split, Gmsh 2.2 ASCII with physical groups."""
    def node(i, j, k):
        return (k * nt + j % nt) * (nr + 1) + i
    pts = []
    for k in range(nz + 1):
        for j in range(nt):
            for i in range(nr + 1):
                r, th = a + (b - a) * i / nr, 2 * math.pi * j / nt
                pts.append((r * math.cos(th), r * math.sin(th), length * k / nz))
    perms = [(0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)]
    def vol(t):
        p = [pts[v] for v in t]
        e = [[p[m][c] - p[0][c] for c in range(3)] for m in (1, 2, 3)]
        return (e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1])
                - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0])
                + e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]))
    tets = []
    for k in range(nz):
        for j in range(nt):
            for i in range(nr):
                for p in perms:
                    c = [i, j, k]
                    t = [node(*c)]
                    for s in range(3):
                        c[p[s]] += 1
                        t.append(node(*c))
                    if vol(t) < 0:
                        t[2], t[3] = t[3], t[2]
                    tets.append(t)
    # Boundary triangles (faces of one tet), named by the grid side they lie on.
    count = {}
    for t in tets:
        for f in range(4):
            tri = tuple(sorted(t[(f + m) % 4] for m in (1, 2, 3)))
            count[tri] = count.get(tri, 0) + 1
    ijk = lambda v: (v % (nr + 1), (v // (nr + 1)) % nt, v // ((nr + 1) * nt))
    groups = {"inner": (2, []), "outer": (3, []), "z0": (4, []), "z1": (5, [])}
    for tri, c in count.items():
        if c != 1:
            continue
        g = [ijk(v) for v in tri]
        if all(x[0] == 0 for x in g): groups["inner"][1].append(tri)
        elif all(x[0] == nr for x in g): groups["outer"][1].append(tri)
        elif all(x[2] == 0 for x in g): groups["z0"][1].append(tri)
        elif all(x[2] == nz for x in g): groups["z1"][1].append(tri)
    with open(path, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n5\n3 1 \"solid\"\n")
        for name, (tag, _) in groups.items():
            f.write(f"2 {tag} \"{name}\"\n")
        f.write("$EndPhysicalNames\n$Nodes\n%d\n" % len(pts))
        for n, p in enumerate(pts):
            f.write("%d %.17g %.17g %.17g\n" % (n + 1, *p))
        f.write("$EndNodes\n$Elements\n")
        ntri = sum(len(v[1]) for v in groups.values())
        f.write("%d\n" % (ntri + len(tets)))
        e = 1
        for name, (tag, tris) in groups.items():
            for t in tris:
                f.write("%d 2 2 %d %d %d %d %d\n" % (e, tag, tag, t[0] + 1, t[1] + 1, t[2] + 1))
                e += 1
        for t in tets:
            f.write("%d 4 2 1 1 %d %d %d %d\n" % (e, *(v + 1 for v in t)))
            e += 1
        f.write("$EndElements\n")
    return len(tets)

def run(name, ranks, steps, petsc, tmp):
    mesh = os.path.join(tmp, name + ".msh")
    if not os.path.exists(mesh):
        write_tube(mesh)
    case = os.path.join(tmp, name + ".yaml")
    opts = f"petsc_options: \"{petsc}\"\n" if petsc else ""
    open(case, "w").write(CASE.format(name=name, mesh=mesh, steps=steps, petsc=opts))
    return run_case(case, ranks, os.path.join(tmp, f"{name}-{ranks}"))

def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=6)
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--cases", nargs="+", default=["tube100k"])
    ap.add_argument("--petsc", default="", help="extra PETSc options (solid_ prefix)")
    a = ap.parse_args()
    result = {"date": time.strftime("%Y-%m-%d"), "machine": platform.processor() or platform.machine(),
              "cores": os.cpu_count(), "petsc_options": a.petsc, "results": {}}
    with tempfile.TemporaryDirectory() as tmp:
        for c in a.cases:
            result["results"][c] = [run(c, r, a.steps, a.petsc, tmp) for r in a.ranks]
    print(json.dumps(result, indent=2))

if __name__ == "__main__":
    main()
