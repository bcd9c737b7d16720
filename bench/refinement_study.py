#!/usr/bin/env python3
"""The dissection's answer against the true lumen's resolution, with the grid convergence index
(issue 56, item 5); prints JSON, then a Markdown table.

usage: bench/refinement_study.py --out DIR [--variants OR EN EX] [--lumen-elements 3 6 9]
                                 [--element-size 3] [--step-ms 10] [--cycles 1] [--ranks 2]
                                 [--layers N --first-layer MM] [--fluid "grad_div_scale: 1"]
                                 [--newton-rtol 1e-4] [--tabulate]
For each variant and each number n of elements across the true lumen's thickness
(`geometry tbad --lumen-elements n`), the rigid-wall template (examples/tbad-study/case.yaml:
the study's inflow and the same RCR outlets for every run, so that only the mesh differs) is
run from rest for --cycles cycles at one step, a frame every step, and its last cycle analysed.
Newton stops at --newton-rtol of each field's first residual (1e-4: docs/study.md's step study
took it as exact); --fluid adds keys to the case's `fluid` mapping (e.g. the grad-div scale).
Folders: DIR/<variant>-n<n>/{geometry,run}. The first cycle from rest is enough for these
metrics: the lumina's split is set by their resistances, not by the Windkessels' settling
(docs/study.md: at n = 6, OR's first and third cycles agree within 0.2 points of FR_FL and
0.1 mmHg of dP).

Per metric (FR_FL and the TL-FL pressure difference at peak systole per station, the tears'
peak-systolic drops) the three finest runs give Roache's grid convergence index by Celik et
al.'s procedure (J. Fluids Eng. 130, 078001, 2008) with the refinement ratio of the TL's edge,
r = n_fine / n_coarse (the rest of the mesh is the same): the observed order p (fixed-point
iteration for unequal ratios), the extrapolated value and GCI_fine = 1.25 |phi_1 - phi_2| /
(r_21^p - 1), in the metric's unit (absolute, as dP crosses zero along the dissection). The
gate of issue 56: between the two finest, FR_FL within 2 points and dP within 1 mmHg.
--tabulate: only compare the runs already in --out (analysing those not yet analysed).
--check-gci: the GCI's arithmetic against Celik et al.'s worked example (CTest
bench.refinement_study.gci).
"""
import argparse, json, math, os, re, subprocess, sys, time

from run_progress import BIN, edit_case

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TEMPLATE = os.path.join(ROOT, "examples", "tbad-study", "case.yaml")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
GATE = {"%": 2.0, "mmHg": 1.0}  # issue 56: between the two finest resolutions


def run(cmd, log):
    with open(log, "w") as f:
        subprocess.run(cmd, check=True, stdout=f, stderr=subprocess.STDOUT, env=ENV)


def simulate(a, variant, n):
    folder = os.path.abspath(os.path.join(a.out, "%s-n%d" % (variant, n)))
    geometry, directory = os.path.join(folder, "geometry"), os.path.join(folder, "run")
    os.makedirs(folder, exist_ok=True)
    if not os.path.exists(os.path.join(geometry, "mesh.msh")):
        cmd = [BIN, "geometry", "tbad", "--variant", variant, "--element-size",
               str(a.element_size), "--lumen-elements", str(n), "-o", geometry]
        if a.layers:
            cmd += ["--layers", str(a.layers), "--first-layer", str(a.first_layer)]
        run(cmd, os.path.join(folder, "geometry.log"))
    case = os.path.join(folder, "case.yaml")
    text = edit_case(open(TEMPLATE).read(), mesh=os.path.join(geometry, "mesh.msh"),
                     step=a.step_ms / 1000, output="every: 1, checkpoint_every: 10, directory: "
                     + directory)
    if a.fluid:
        text = text.replace("fluid: {", "fluid: {%s, " % a.fluid)
    open(case, "w").write(text + "newton: {rtol: %r}\n" % a.newton_rtol)
    period = float(re.search(r"period: ([\d.e+-]+)", text).group(1))  # the inflow's
    steps = round(a.cycles * period * 1000 / a.step_ms)
    cmd = [BIN, "run", case, "--steps", str(steps)]
    if a.ranks > 1:
        cmd = ["mpirun", "-n", str(a.ranks)] + cmd
    start = time.time()
    run(cmd, os.path.join(folder, "run.log"))
    with open(os.path.join(folder, "wall_time_s"), "w") as f:
        f.write("%.0f\n" % (time.time() - start))


def measured(a, variant, n):
    """The run's headline metrics (name -> (value, unit)) and its size and cost."""
    folder = os.path.join(a.out, "%s-n%d" % (variant, n))
    metrics = os.path.join(folder, "run", "analysis", "metrics.json")
    if not (a.tabulate and os.path.exists(metrics)):  # --tabulate reuses an analysis
        subprocess.run([BIN, "analyze", os.path.join(folder, "run"), "--case",
                        os.path.join(folder, "case.yaml"), "--landmarks",
                        os.path.join(folder, "geometry", "landmarks.json")],
                       check=True, capture_output=True)
    m = json.load(open(metrics))
    values = {}
    for k, s in sorted(m["stations"].items()):
        values["FR_FL station %s" % k] = (s["FR_FL_percent"], "%")
    for k, s in sorted(m["stations"].items()):
        values["dP peak systole station %s" % k] = (s["dP_TL_minus_FL_peak_systole_mmHg"], "mmHg")
    for name in ["entry_tear_inlet_to_FL1", "exit_tear_FL5_to_outlet"]:
        values[name + " peak systole"] = (m["pressure_drops"][name]["peak_systole_mmHg"], "mmHg")
    log = open(os.path.join(folder, "run.log")).read()
    tets = int(re.search(r"(\d+) tets", log).group(1))
    steps = [tuple(map(int, x)) for x in re.findall(r"Newton (\d+) .*?KSP +(\d+)", log)]
    # None when an analysis has no such measure: printed "-", never as a perfect balance.
    shares = [s.get("flow_conservation_vs_DAo_prox_relative_to_peak")
              for s in m["stations"].values()]
    balance = None if None in shares else max(abs(x) for x in shares)
    wall = os.path.join(folder, "wall_time_s")
    cost = {"fluid_tets": tets, "steps": len(steps),
            "newton_per_step": sum(s[0] for s in steps) / max(1, len(steps)),
            "ksp_per_step": sum(s[1] for s in steps) / max(1, len(steps)),
            "wall_time_s": float(open(wall).read()) if os.path.exists(wall) else None,
            "mass_balance_relative_to_peak": balance}
    return values, cost


def gci(n, phi):
    """Celik et al. (2008) on three resolutions n[0] < n[1] < n[2] (elements across, so
    h ~ 1/n) with values phi[0..2]: observed order, extrapolated value, fine GCI (absolute)."""
    r21, r32 = n[2] / n[1], n[1] / n[0]
    e21, e32 = phi[1] - phi[2], phi[0] - phi[1]  # Celik's 1 = fine: e21 = phi_2 - phi_1
    out = {"change_fine": phi[2] - phi[1]}
    if e21 == 0 or e32 == 0:
        return dict(out, order=None, extrapolated=phi[2], gci_fine=0.0, monotone=True)
    s = math.copysign(1.0, e32 / e21)
    p = abs(math.log(abs(e32 / e21))) / math.log(r21)
    for _ in range(100):
        q = math.log((r21 ** p - s) / (r32 ** p - s)) if (r32 ** p - s) > 0 else 0.0
        p_new = abs(math.log(abs(e32 / e21)) + q) / math.log(r21)
        if abs(p_new - p) < 1e-10:
            break
        p = p_new
    p = max(p, 1e-3)
    extrapolated = (r21 ** p * phi[2] - phi[1]) / (r21 ** p - 1)
    return dict(out, order=p, extrapolated=extrapolated,
                gci_fine=1.25 * abs(e21) / (r21 ** p - 1), monotone=s > 0)


def check_gci():
    """Celik et al. (2008), Table 1, first column: phi 6.063 / 5.972 / 5.863 on grids refined by
    r21 = 1.5 and r32 = 4/3 give p = 1.53, phi_ext = 6.1685 and GCI_fine = 2.17 %; the digits
    the paper prints are the tolerances. Returns the exit status (CTest runs it)."""
    g = gci([1.0, 4 / 3, 2.0], [5.863, 5.972, 6.063])
    ok = (abs(g["order"] - 1.53) < 0.005 and abs(g["extrapolated"] - 6.1685) < 5e-4
          and abs(100 * g["gci_fine"] / 6.063 - 2.17) < 0.005 and g["monotone"])
    print("GCI against Celik et al. 2008:", "ok" if ok else "WRONG", g)
    return 0 if ok else 1


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--check-gci", action="store_true", help="the GCI against Celik's example")
    ap.add_argument("--out")
    ap.add_argument("--variants", nargs="+", default=["OR", "EN", "EX"])
    ap.add_argument("--lumen-elements", type=int, nargs="+", default=[3, 6, 9])
    ap.add_argument("--element-size", type=float, default=3.0)
    ap.add_argument("--step-ms", type=float, default=10.0)
    ap.add_argument("--cycles", type=int, default=1)
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--layers", type=int, default=0)
    ap.add_argument("--first-layer", type=float, default=0.2)
    ap.add_argument("--fluid", default="", help="more fluid keys, e.g. 'grad_div_scale: 1'")
    ap.add_argument("--newton-rtol", type=float, default=1e-4)
    ap.add_argument("--tabulate", action="store_true")
    a = ap.parse_args()
    if a.check_gci:
        sys.exit(check_gci())
    if not a.out:
        ap.error("--out is required")
    ns = sorted(a.lumen_elements)
    report = {"element_size_mm": a.element_size, "step_ms": a.step_ms, "cycles": a.cycles,
              "layers": a.layers, "first_layer_mm": a.first_layer, "fluid": a.fluid,
              "newton_rtol": a.newton_rtol, "lumen_elements": ns, "gate": GATE, "variants": {}}
    for v in a.variants:
        runs = {}
        for n in ns:
            if not a.tabulate:
                simulate(a, v, n)
            runs[n] = measured(a, v, n)
        entry = {"runs": {n: {"cost": c, "values": {k: x[0] for k, x in vals.items()}}
                          for n, (vals, c) in runs.items()}, "metrics": {}}
        for k, (_, unit) in runs[ns[-1]][0].items():
            phi = [runs[n][0][k][0] for n in ns]
            if len(ns) >= 3:
                g = gci(ns[-3:], phi[-3:])
            else:  # two resolutions give the change, one gives the values only
                g = {"change_fine": phi[-1] - phi[-2] if len(ns) == 2 else None}
            g["unit"] = unit
            g["within_gate"] = g["change_fine"] is not None and abs(g["change_fine"]) <= GATE[unit]
            entry["metrics"][k] = g
        entry["gate_met"] = all(g["within_gate"] for g in entry["metrics"].values())
        report["variants"][v] = entry
    json.dump(report, sys.stdout, indent=2)
    print("\n")
    for v, entry in report["variants"].items():
        print("\n%s (gate %s)\n" % (v, "met" if entry["gate_met"] else "NOT met"))
        print("| metric | " + " | ".join("n = %d" % n for n in ns)
              + " | finest change | order | extrapolated | GCI_fine |")
        print("|---|" + "---|" * (len(ns) + 4))
        for k, g in entry["metrics"].items():
            vals = " | ".join("%.2f" % entry["runs"][n]["values"][k] for n in ns)
            order = "%.2f%s" % (g["order"], "" if g["monotone"] else " (osc.)") \
                if g.get("order") else "-"
            ex = "%.2f" % g["extrapolated"] if "extrapolated" in g else "-"
            gf = "%.2f" % g["gci_fine"] if "gci_fine" in g else "-"
            change = "-" if g["change_fine"] is None else "%+.2f%s" % (
                g["change_fine"], "" if g["within_gate"] else " (!)")
            print("| %s [%s] | %s | %s | %s | %s | %s |" % (k, g["unit"], vals, change, order,
                                                              ex, gf))
        print("| fluid tets | " + " | ".join(
            "%d" % entry["runs"][n]["cost"]["fluid_tets"] for n in ns) + " | | | | |")
        print("| Newton / KSP per step | " + " | ".join(
            "%.1f / %.0f" % (entry["runs"][n]["cost"]["newton_per_step"],
                             entry["runs"][n]["cost"]["ksp_per_step"]) for n in ns) + " | | | | |")
        print("| mass balance / peak flow | " + " | ".join(
            "-" if entry["runs"][n]["cost"]["mass_balance_relative_to_peak"] is None else
            "%.1e" % entry["runs"][n]["cost"]["mass_balance_relative_to_peak"] for n in ns)
            + " | | | | |")


if __name__ == "__main__":
    main()
