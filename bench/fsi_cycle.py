#!/usr/bin/env python3
"""The study's resolution over the cardiac cycle (issue 23): s/step, Newton and Krylov
iterations, assembly/solve split and peak memory per process of the FSI dissection at a
fine element size, from a periodic state at several phases of the cycle; prints JSON.

usage: bench/fsi_cycle.py --source-case CASE --source-run DIR [--element-size 1.0]
                          [--step 0.005] [--phases 0.08 0.2 0.32 0.6] [--steps 3]
                          [--ranks 1 2] [--mesh DIR] [--stabilization-time-scale T]
  --source-case/--source-run: a periodic coarse FSI run of the built-in dissection (OR) and
      its case, e.g. the demo study's OR (results/tbad-demo/OR/run and its tuned case): its
      checkpoint at a cycle's end is the state the phases start from.
For each phase (a fraction of the cycle after the checkpoint): the coarse run continued from
its checkpoint to that time (its own step), then the fine mesh (`geometry tbad --variant OR
--element-size`, made once, or --mesh) started from that state interpolated (`run
--start-from --start-case`), at --step for --steps steps; the first is start-up (the
preconditioner's first setup, the interpolated state's settling) and not timed. Newton and
solver options as the source case says. --stabilization-time-scale T: the fine runs' tau_M
time term at T seconds instead of their step (fluid.stabilization_time_scale, docs/study.md).
"""
import argparse, json, os, platform, re, subprocess, sys, tempfile, time

from run_progress import BIN, edit_case, run_case


def with_keys(text, output, mesh=None, step=None, checkpoint_every=0, time_scale=None):
    """The case text with its mesh file, time step and output replaced, cycles unbounded."""
    return edit_case(text, mesh=mesh, step=step, time_scale=time_scale, max_cycles=50,
                     output="every: 0, checkpoint_every: %d, directory: %s"
                     % (checkpoint_every, output))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source-case", required=True)
    ap.add_argument("--source-run", required=True)
    ap.add_argument("--element-size", type=float, default=1.0)
    ap.add_argument("--mesh", help="a folder of `geometry tbad` at that size (made if absent)")
    ap.add_argument("--step", type=float, default=0.005)
    ap.add_argument("--phases", type=float, nargs="+", default=[0.08, 0.2, 0.32, 0.6])
    ap.add_argument("--steps", type=int, default=3)
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--stabilization-time-scale", type=float)
    a = ap.parse_args()
    source_text = open(a.source_case).read()
    coarse_step = float(re.search(r"time: \{step: ([^,]*),", source_text).group(1))
    period = float(re.search(r"period: ([\d.e+-]+)", source_text).group(1))
    run_dir = os.path.abspath(a.source_run)
    t0 = float(open(os.path.join(run_dir, "faces.csv")).read().strip().split("\n")[-1]
               .split(",")[1])  # the last row: the checkpoint's time at the run's end
    result = {"date": time.strftime("%Y-%m-%d"),
              "machine": platform.processor() or platform.machine(), "cores": os.cpu_count(),
              "element_size_mm": a.element_size, "step_s": a.step,
              "stabilization_time_scale_s": a.stabilization_time_scale or a.step,
              "source_run": run_dir,
              "source_time_s": t0, "phases": []}
    with tempfile.TemporaryDirectory() as tmp:
        mesh_dir = os.path.abspath(a.mesh or os.path.join(tmp, "geometry"))
        if not os.path.exists(os.path.join(mesh_dir, "mesh.msh")):
            subprocess.run([BIN, "geometry", "tbad", "--variant", "OR", "--element-size",
                            str(a.element_size), "-o", mesh_dir], check=True,
                           capture_output=True)
        for phase in a.phases:
            t = t0 + phase * period
            coarse_dir = os.path.join(tmp, "coarse-%g" % phase)
            coarse_case = os.path.join(tmp, "coarse-%g.yaml" % phase)
            open(coarse_case, "w").write(with_keys(source_text, coarse_dir,
                                                   checkpoint_every=1000000))
            subprocess.run([BIN, "run", coarse_case, "-q", "--start-from",
                            os.path.join(run_dir, "checkpoint.bin"),
                            "--steps", str(round(t / coarse_step))], check=True,
                           capture_output=True)
            fine_case = os.path.join(tmp, "fine-%g.yaml" % phase)
            row = {"phase": phase, "time_s": t, "runs": []}
            for ranks in a.ranks:
                fine_dir = os.path.join(tmp, "fine-%g-%d" % (phase, ranks))
                open(fine_case, "w").write(with_keys(source_text, fine_dir,
                                                     os.path.join(mesh_dir, "mesh.msh"), a.step,
                                                     time_scale=a.stabilization_time_scale))
                first = round(t / a.step)
                row["runs"].append(run_case(fine_case, ranks, fine_dir, first + a.steps,
                                            extra=["--start-from",
                                                   os.path.join(coarse_dir, "checkpoint.bin"),
                                                   "--start-case", coarse_case]))
                # each run as it ends: a long benchmark cut short keeps what it measured
                print(json.dumps({"phase": phase, **row["runs"][-1]}), file=sys.stderr,
                      flush=True)
            result["phases"].append(row)
    for ranks in a.ranks:  # over the phases: the cycle's mean per step
        runs = [r for p in result["phases"] for r in p["runs"]
                if r["ranks"] == ranks and "error" not in r]
        if runs:
            keys = ["seconds_per_step", "assembly_seconds_per_step", "solve_seconds_per_step",
                    "newton_per_step", "ksp_per_step"]
            mean = {k: sum(r[k] for r in runs) / len(runs) for k in keys}
            mean["peak_rss_MiB_one_process_max"] = max(r["peak_rss_MiB_one_process_max"]
                                                       for r in runs)
            mean["krylov_per_newton"] = mean["ksp_per_step"] / mean["newton_per_step"]
            mean["hours_per_cycle"] = mean["seconds_per_step"] * period / a.step / 3600
            result.setdefault("mean_over_phases", {})[str(ranks)] = mean
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
