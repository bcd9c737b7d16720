#!/usr/bin/env python3
"""`tearflow rom sweep` of the built-in dissection, rigid and compliant; prints JSON.

usage: bench/rom_sweep.py [--steps 20] [--keep DIR]

Builds the OR model (`geometry tbad`, 4.5 mm, as the demo), calibrates its rigid coefficients
on the stored 3D result (tests/data/rom/OR-rigid), and sweeps entry and exit tears over 30 to
300 mm^2 on a steps x steps grid with the demo's rigid case and with its compliant (FSI) case
(uncalibrated compliant coefficients: the sweep's cost does not depend on them). Reports the
model's own time for all variants (as the command prints it), the command's wall and CPU
time and peak memory (GNU time), and the cycles to periodicity. One process at a time (the
sweep runs on one core): run it on a quiet machine.
"""
import argparse, csv, json, os, re, subprocess, time

from timing import BIN, ROOT, or_model, work_dir

DATA = os.path.join(ROOT, "tests", "data", "rom")


def case(variant, model, tmp):
    text = open(os.path.join(DATA, variant + ".yaml")).read().replace("MODEL/", model + "/")
    path = os.path.join(tmp, variant + ".yaml")
    open(path, "w").write(text)
    return path


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=20)
    ap.add_argument("--keep")
    a = ap.parse_args()
    tmp = work_dir(a.keep, "rom")
    model = or_model(tmp, 4.5)
    rigid = case("OR-rigid", model, tmp)
    subprocess.run([BIN, "rom", "calibrate", model, "--run", os.path.join(DATA, "OR-rigid"),
                    "--case", rigid], check=True, stdout=subprocess.DEVNULL)
    out = {"model": "OR, geometry tbad --element-size 4.5", "grid": f"{a.steps} x {a.steps}",
           "entry_mm2": "30:300", "exit_mm2": "30:300", "runs": []}
    for label, variant in (("rigid", "OR-rigid"), ("compliant", "OR-fsi")):
        path = case(variant, model, tmp)
        sweep = os.path.join(tmp, "sweep-" + label)
        t0 = time.perf_counter()
        p = subprocess.run(["/usr/bin/time", "-f", "peak_kb=%M cpu_s=%U", BIN, "rom", "sweep",
                            model, "--case", path, "--entry", "30:300", "--exit", "30:300",
                            "--steps", str(a.steps), "-o", sweep],
                           check=True, capture_output=True, text=True)
        wall = time.perf_counter() - t0
        model_s = float(re.search(r"variants in ([\d.]+) s", p.stdout).group(1))
        cycles = [int(r["cycles"]) for r in csv.DictReader(open(os.path.join(sweep, "sweep.csv")))]
        out["runs"].append({
            "walls": label, "variants": len(cycles), "model_s": model_s,
            "per_variant_ms": round(1e3 * model_s / len(cycles), 2),
            "command_wall_s": round(wall, 2),
            "command_cpu_s": float(re.search(r"cpu_s=([\d.]+)", p.stderr).group(1)),
            "peak_mb": round(int(re.search(r"peak_kb=(\d+)", p.stderr).group(1)) / 1024),
            "cycles_min": min(cycles), "cycles_max": max(cycles)})
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
