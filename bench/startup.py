#!/usr/bin/env python3
"""Cycle-to-cycle change per cardiac cycle with and without the 0D start-up; prints JSON.

usage: bench/startup.py [--cycles N]
A coarse pipe (R 1 cm, L 5 cm, element size 2.5 mm) with the built-in case's aortic-like
inflow, closed by one RCR with the reference study's OR totals (R_d C = 0.85 s, comparable
to the 1 s period, so the outlet remembers its initial state for several cycles). Runs
`start: periodic_0d` (the default) and `start: rest` with the distal pressure starting at 0,
and reports each run's `change_from_previous` from cycles.json.
"""
import argparse, json, os, subprocess, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "tearflow")

CASE = """name: startup-{start}
mesh: {{pipe: {{radius: 0.01, length: 0.05, element_size: 0.0025}}}}
time: {{step: 0.01, cycles: {cycles}, start: {start}}}
boundary_conditions:
  - {{face: wall, type: no_slip}}
  - face: inlet
    type: inflow
    flow: {{times: [0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.5, 0.6, 0.8],
            values: [2, 30, 75, 90, 70, 40, 12, -6, 0, 4, 3, 2], units: mL/s, period: 1.0}}
  - {{face: outlet, type: rcr, proximal_resistance: 2.4e7, capacitance: 6.74e-9,
      distal_resistance: 1.26e8{initial}}}
output: {{every: 0}}
"""

def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cycles", type=int, default=8)
    args = ap.parse_args()
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    result = {"case": "pipe R 1 cm, L 5 cm, h 2.5 mm; RCR R_p 2.4e7, C 6.74e-9, R_d 1.26e8",
              "runs": {}}
    with tempfile.TemporaryDirectory() as tmp:
        for start in ["periodic_0d", "rest"]:
            path = os.path.join(tmp, f"{start}.yaml")
            initial = ", initial_distal_pressure: 0" if start == "rest" else ""
            open(path, "w").write(CASE.format(start=start, cycles=args.cycles, initial=initial))
            out = os.path.join(tmp, start)
            p = subprocess.run([BIN, "run", path, "-q", "-o", out], capture_output=True,
                               text=True, env=env)
            if p.returncode != 0:
                result["runs"][start] = {"error": p.stdout[-1000:] + p.stderr[-1000:]}
                continue
            cycles = json.load(open(os.path.join(out, "cycles.json")))["cycles"]
            result["runs"][start] = {
                "change_per_cycle": [c["change_from_previous"] for c in cycles],
                "outlet_mean_pressure_mmHg_per_cycle":
                    [round(c["faces"]["outlet"]["mean_pressure_mmHg"], 3) for c in cycles]}
    print(json.dumps(result, indent=2))

if __name__ == "__main__":
    main()
