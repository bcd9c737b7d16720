#!/usr/bin/env python3
"""One case under several sets of solver options: the same steps from the same start, each
set's seconds per step, Newton and Krylov iterations per step and the total; prints JSON.

usage: bench/fsi_options.py --case CASE [--steps 50] [--ranks 2] --options "SET" ["SET" ...]
  --case: a case file as `tearflow run` takes it, e.g. the demo study's OR
      (results/tbad-demo/OR/case.yaml: FSI at 4.5 mm, dt 20 ms, from the 0D periodic state);
  --options: PETSc options per run, given as PETSC_OPTIONS (they come after the case's and
      the defaults, so they win); "" runs the defaults.
The first step is start-up and is left out of the per-step means (run_progress.py), not of
`seconds_total`, the run's wall time from start to end.
"""
import argparse, json, os, platform, tempfile, time

from run_progress import run_case


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--case", required=True)
    ap.add_argument("--steps", type=int, default=50)
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--options", nargs="+", required=True)
    args = ap.parse_args()
    case = os.path.abspath(args.case)
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        for i, options in enumerate(args.options):
            os.environ["PETSC_OPTIONS"] = options
            start = time.time()
            r = run_case(case, args.ranks, os.path.join(tmp, "run%d" % i), steps=args.steps)
            r["seconds_total"] = time.time() - start
            r["options"] = options
            results.append(r)
    os.environ.pop("PETSC_OPTIONS", None)
    print(json.dumps({"benchmark": "fsi_options", "case": case, "steps": args.steps,
                      "machine": platform.node(), "cores": os.cpu_count(),
                      "load_average_at_end": os.getloadavg()[0], "runs": results}, indent=2))


if __name__ == "__main__":
    main()
