#!/usr/bin/env python3
"""The time step the study's metrics need (issue 23, item 2); prints JSON and a Markdown table.

usage: bench/step_study.py --source-case CASE --source-run DIR --out DIR
                           [--steps-ms 20 10 5 2.5 1] [--cycles 1] [--frame-ms 10]
                           [--newton-rtol 1e-4] [--ranks 2] [--stabilization-time-scale T]
                           [--tabulate]
A periodic FSI run of the dissection (its checkpoint at a cycle's end, e.g. the demo's OR,
results/tbad-demo/OR/run, and its case with the outlets it ended with) is continued at each
step for --cycles cycles (`run --start-from`, its outlets fixed), each frame --frame-ms apart
(the same frames' times at every step), and the last cycle analysed (`analyze --case`).
The headline metrics (FR_FL and dP TL-FL at peak systole and end diastole per station, the
tears' pressure drops, the inlet's pressures, AAo dilation) are compared with the finest
step's: the largest step whose pressures are all within 0.5 mmHg and whose FR_FL and
dilation are within 2 % of the finest's is the one the study's template takes.
--stabilization-time-scale T: tau_M's time term at T seconds in every run instead of each
run's step (fluid.stabilization_time_scale), which separates the time integration's accuracy
from the stabilization's dependence on the step (docs/study.md).
--tabulate: only analyse and compare the runs already in --out.
"""
import argparse, json, os, re, subprocess, sys

from run_progress import BIN, edit_case

ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def case_text(text, step, rtol, every, directory, time_scale=None):
    return edit_case(text, step=step, time_scale=time_scale, max_cycles=50, rtol=rtol,
                     output="every: %d, checkpoint_every: %d, directory: %s"
                     % (every, 10 * every, directory))


def metrics(m):
    """The headline metrics of one analysis: name -> (value, unit)."""
    out = {}
    for k, s in sorted(m["stations"].items()):
        out["FR_FL station %s" % k] = (s["FR_FL_percent"], "%")
        out["dP peak systole station %s" % k] = (s["dP_TL_minus_FL_peak_systole_mmHg"], "mmHg")
        out["dP end diastole station %s" % k] = (s["dP_TL_minus_FL_end_diastole_mmHg"], "mmHg")
    for name, d in sorted(m["pressure_drops"].items()):
        out[name + " mean"] = (d["mean_mmHg"], "mmHg")
        out[name + " peak systole"] = (d["peak_systole_mmHg"], "mmHg")
    for k in ["inlet_systolic_pressure_mmHg", "inlet_diastolic_pressure_mmHg",
              "inlet_mean_pressure_mmHg"]:
        out[k] = (m["achieved"][k], "mmHg")
    out["AAo min-to-max dilation"] = (m["AAo_min_to_max_dilation_percent"], "%")
    return out


def within(value, finest, unit):
    return abs(value - finest) <= (0.5 if unit == "mmHg" else 0.02 * abs(finest))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source-case", required=True)
    ap.add_argument("--source-run", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--steps-ms", type=float, nargs="+", default=[20, 10, 5, 2.5, 1])
    ap.add_argument("--cycles", type=int, default=1)
    ap.add_argument("--frame-ms", type=float, default=10)
    ap.add_argument("--newton-rtol", type=float, default=1e-4)
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--stabilization-time-scale", type=float)
    ap.add_argument("--tabulate", action="store_true")
    a = ap.parse_args()
    text = open(a.source_case).read()
    period = float(re.search(r"period: ([\d.e+-]+)", text).group(1))
    run_dir = os.path.abspath(a.source_run)
    t0 = float(open(os.path.join(run_dir, "faces.csv")).read().strip().split("\n")[-1]
               .split(",")[1])
    os.makedirs(a.out, exist_ok=True)
    results = {}
    for ms in a.steps_ms:
        name = "dt%g" % ms
        directory = os.path.abspath(os.path.join(a.out, name))
        case = directory + ".yaml"
        every = max(1, round(a.frame_ms / ms))
        if not a.tabulate:
            open(case, "w").write(case_text(text, ms / 1000, a.newton_rtol, every, directory,
                                               a.stabilization_time_scale))
            last = round((t0 + a.cycles * period) / (ms / 1000))
            cmd = [BIN, "run", case, "--start-from", os.path.join(run_dir, "checkpoint.bin"),
                   "--steps", str(last)]
            if a.ranks > 1:
                cmd = ["mpirun", "-n", str(a.ranks)] + cmd
            with open(directory + ".log", "w") as log:
                subprocess.run(cmd, check=True, stdout=log, stderr=subprocess.STDOUT, env=ENV)
        mesh = re.search(r"mesh: \{file: ([^,]*),", text).group(1)
        landmarks = os.path.join(os.path.dirname(mesh), "landmarks.json")
        subprocess.run([BIN, "analyze", directory, "--case", case, "--landmarks", landmarks],
                       check=True, capture_output=True)
        with open(os.path.join(directory, "analysis", "metrics.json")) as f:
            results[ms] = metrics(json.load(f))
    finest = min(results)
    table = {"finest_step_ms": finest, "steps": {}}
    for ms, values in sorted(results.items(), reverse=True):
        table["steps"][ms] = {k: {"value": v, "unit": u, "difference": v - results[finest][k][0],
                                   "within": within(v, results[finest][k][0], u)}
                              for k, (v, u) in values.items()}
    passing = [ms for ms, r in table["steps"].items() if all(x["within"] for x in r.values())]
    table["largest_step_within_ms"] = max(passing)
    json.dump(table, sys.stdout, indent=2)
    steps = sorted(results, reverse=True)
    print("\n\n| metric | " + " | ".join("dt %g ms" % s for s in steps) + " |")
    print("|---|" + "---|" * len(steps))
    for k, (v, u) in results[finest].items():
        cells = []
        for s in steps:
            x = table["steps"][s][k]
            cells.append("%.2f" % x["value"] if s == finest else "%+.2f%s" % (
                x["difference"], "" if x["within"] else " (!)"))
        print("| %s [%s] | %s |" % (k, u, " | ".join(cells)))


if __name__ == "__main__":
    main()
