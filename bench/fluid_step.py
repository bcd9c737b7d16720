#!/usr/bin/env python3
"""Time per step of the rigid-wall flow solver; prints one JSON object.

usage: bench/fluid_step.py [--steps N] [--ranks 1 2] [--cases pipe50k pipe400k pipe-rcr]
Cases: pipe50k / pipe400k are the built-in pipe (R 1 cm, L 10 cm, element size 1.4 / 0.7 mm)
with a pulsatile inflow and a resistance outlet; pipe-rcr is examples/pipe-rcr.
Reports per case and rank count: mean seconds per step, assembly seconds per step, solve
seconds per step, Newton and KSP iterations per step, peak resident memory (max over ranks).
"""
import argparse, json, os, re, subprocess, sys, tempfile, time, platform

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "tearflow")

PIPE = """name: {name}
mesh: {{pipe: {{radius: 0.01, length: 0.1, element_size: {h}}}}}
fluid: {{density: 1060, viscosity: 0.004}}
time: {{step: 0.005, steps: {steps}, spectral_radius: 0.5}}
boundary_conditions:
  - {{face: wall, type: no_slip}}
  - face: inlet
    type: inflow
    flow: {{times: [0, 0.1, 0.2, 0.3, 0.5], values: [10, 60, 90, 40, 10], units: mL/s, period: 1.0}}
  - {{face: outlet, type: resistance, resistance: 1.0e8}}
newton: {{max_iterations: 10, rtol: 1.0e-6, atol: 1.0e-12}}
output: {{every: 0}}
"""

def case_file(name, steps, tmp):
    path = os.path.join(tmp, name + ".yaml")
    if name == "pipe-rcr":
        text = open(os.path.join(ROOT, "examples/pipe-rcr/case.yaml")).read()
        text = re.sub(r"(steps|cycles): \d+", f"steps: {steps}", text)
        text = text.replace("../../../shared", os.path.join(ROOT, "..", "shared"))
        text = re.sub(r"output: .*", "output: {every: 0}", text)
    else:
        h = {"pipe50k": 0.0014, "pipe400k": 0.0007}[name]
        text = PIPE.format(name=name, h=h, steps=steps)
    open(path, "w").write(text)
    return path

LINE = re.compile(r"step\s+(\d+)/\d+.*Newton (\d+) \(\|R\| ([\d.e+-]+) -> ([\d.e+-]+)\)\s+KSP\s+(\d+)\s+([\d.]+) s/step \(assembly ([\d.]+) s\)")

def run(name, ranks, steps, tmp):
    cmd = ["/usr/bin/time", "-f", "MAXRSS %M", BIN, "run", case_file(name, steps, tmp),
           "-o", os.path.join(tmp, f"{name}-{ranks}")]
    if ranks > 1:
        cmd = ["/usr/bin/time", "-f", "MAXRSS %M", "mpirun", "-n", str(ranks), BIN, "run",
               case_file(name, steps, tmp), "-o", os.path.join(tmp, f"{name}-{ranks}")]
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    out = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if out.returncode != 0:
        return {"error": out.stdout[-2000:] + out.stderr[-2000:]}
    # (step, newton, |R| initial, |R| final, ksp, s/step, assembly s/step)
    rows = [tuple(map(float, m.groups())) for m in LINE.finditer(out.stdout)]
    rows = rows[1:] if len(rows) > 2 else rows  # the first step includes start-up costs
    mesh = re.search(r"mesh: (\d+) nodes, (\d+) tets", out.stdout)
    rss = max(int(x) for x in re.findall(r"MAXRSS (\d+)", out.stderr))
    n = len(rows)
    return {
        "ranks": ranks, "nodes": int(mesh.group(1)), "tets": int(mesh.group(2)),
        "steps_timed": n,
        "seconds_per_step": sum(r[5] for r in rows) / n,
        "assembly_seconds_per_step": sum(r[6] for r in rows) / n,
        "solve_seconds_per_step": sum(r[5] - r[6] for r in rows) / n,
        "newton_per_step": sum(r[1] for r in rows) / n,
        "ksp_per_step": sum(r[4] for r in rows) / n,
        # Newton convergence: the least residual reduction |R_final| / |R_initial| of any step.
        "worst_relative_residual": max(r[3] / r[2] for r in rows if r[2] > 0),
        "peak_rss_MiB_one_process_max": rss / 1024.0,
    }

def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=6)
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--cases", nargs="+", default=["pipe50k", "pipe400k", "pipe-rcr"])
    a = ap.parse_args()
    result = {"date": time.strftime("%Y-%m-%d"), "machine": platform.processor() or platform.machine(),
              "cores": os.cpu_count(), "results": {}}
    with tempfile.TemporaryDirectory() as tmp:
        for c in a.cases:
            result["results"][c] = [run(c, r, a.steps, tmp) for r in a.ranks]
    print(json.dumps(result, indent=2))

if __name__ == "__main__":
    main()
