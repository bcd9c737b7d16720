#!/usr/bin/env python3
"""The study's 2D scans of a TBAD run, end to end; prints JSON.

usage: bench/mri_2d.py RUN_DIR --case CASE --landmarks FILE [--seeds 3] [--thickness 5mm,3mm]
       [--keep DIR]
RUN_DIR is an FSI run's output (the README's demo study writes OR/run, OR/case.yaml and
OR/geometry/landmarks.json). Two measurements, each against the run itself:

1. 2D cine at every landmark plane (`tearflow mri synthesize --scan-type cine`: 1 mm pixels,
   80 mm field of view, 30 frames, SNR 20, per seed and slice thickness), tracked by
   `tearflow mri cine` at the five stations (TLk / FLk) and at AAo and DAo_dist: per landmark
   the worst frame's |A_mri / A_run - 1|, A_run the run's section area averaged over the
   frame's window (linear between saved frames), the run's own area swing, and the label
   swaps; and the same against the run's area averaged over the slab as the synthetic
   scanner samples it (the planes at -t/3, 0, +t/3 along the normal): the slice thickness's
   own partial volume taken out, what remains is the tracking's error.
2. 2D phase contrast across the inflow and every outlet (`--scan-type pc --case`: 1.5 mm
   pixels, 6 mm slices, tilted 15 degrees, SNR 20, venc 1.5 m/s), made into a case and
   targets by `tearflow mri inflow`: mean and peak inflow and the outlet splits against the
   run's last cycle in faces.csv.
"""
import argparse, csv, json, os, subprocess, tempfile, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "tearflow")


def run(cmd):
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t0


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def slab_analysis(run_dir, landmarks, case, thickness_m, tmp):
    """The run's areas averaged over the planes at -t/3, 0, +t/3: a folder of <landmark>.csv."""
    os.makedirs(tmp, exist_ok=True)
    base = json.load(open(landmarks))
    scale = 1e3 if base.get("length_unit", "m") == "mm" else 1.0  # the file's length unit
    tables = []
    for k, offset in enumerate((-scale * thickness_m / 3, 0.0, scale * thickness_m / 3)):
        shifted = json.loads(json.dumps(base))
        shifted["planes"] = [p for p in shifted["planes"] if p["name"] not in ("inlet", "outlet")]
        for p in shifted["planes"]:  # (the inlet and outlet planes lie on the faces)
            n = p["normal"]
            norm = sum(c * c for c in n) ** 0.5
            p["origin"] = [o + offset * c / norm for o, c in zip(p["origin"], n)]
            if p.get("point") is not None:
                p["point"] = [o + offset * c / norm for o, c in zip(p["point"], n)]
        path = f"{tmp}/slab{k}.json"
        json.dump(shifted, open(path, "w"))
        run([BIN, "analyze", run_dir, "--landmarks", path, "--case", case, "-o", f"{tmp}/slab{k}", "-q"])
        tables.append(f"{tmp}/slab{k}")
    out = f"{tmp}/slab_mean"
    os.makedirs(out, exist_ok=True)
    for name in os.listdir(tables[0]):
        if not name.endswith(".csv") or name == "pressure_difference.csv":
            continue
        parts = [rows(os.path.join(t, name)) for t in tables]
        with open(os.path.join(out, name), "w") as f:
            f.write("time_s,area_mm2\n")
            for r in zip(*parts):
                f.write(f"{r[0]['time_s']},{sum(float(x['area_mm2']) for x in r) / 3}\n")
    return out


def area_errors(measured_dir, analysis_dir):
    m = rows(os.path.join(measured_dir, "area.csv"))
    out = {}
    for column in [c for c in m[0] if c.endswith("_mm2")]:
        lm = column[:-4]
        s = [(float(r["time_s"]), float(r["area_mm2"])) for r in rows(f"{analysis_dir}/{lm}.csv")]
        t0, T = s[0][0], s[-1][0] - s[0][0]

        def at(t):
            t = t0 + (t - t0) % T
            i = next(i for i in range(1, len(s)) if s[i][0] >= t)
            w = (t - s[i - 1][0]) / (s[i][0] - s[i - 1][0])
            return (1 - w) * s[i - 1][1] + w * s[i][1]

        worst = swing = 0.0
        dt = T / len(m)
        for r in m:
            t = t0 + float(r["time_s"])
            expected = sum(at(t + ((q + 0.5) / 40 - 0.5) * dt) for q in range(40)) / 40
            worst = max(worst, abs(float(r[column]) / expected - 1))
            swing = max(swing, abs(expected / at(t0) - 1))
        out[lm] = {"worst_percent": round(100 * worst, 2), "run_swing_percent": round(100 * swing, 2),
                   "A_0_mm2": round(at(t0), 1)}
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("run_dir")
    ap.add_argument("--case", required=True)
    ap.add_argument("--landmarks", required=True)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--thickness", default="5mm,3mm")
    ap.add_argument("--keep")
    a = ap.parse_args()
    tmp = a.keep or tempfile.mkdtemp(prefix="tearflow-bench-mri2d-")
    analysis = os.path.join(a.run_dir, "analysis")
    result = {"run": os.path.abspath(a.run_dir), "cine": {}, "phase_contrast": {}}
    at = [f"{k}={tmp}/cine/station{k}" for k in range(1, 6)] + \
         [f"AAo={tmp}/cine/AAo", f"DAo_dist={tmp}/cine/DAo_dist"]
    for thickness in a.thickness.split(","):
        mm = float(thickness.rstrip("m")) * 1e-3
        slab = slab_analysis(a.run_dir, a.landmarks, a.case, mm, f"{tmp}/slab-{thickness}")
        per_seed = []
        for seed in range(1, a.seeds + 1):
            synth = run([BIN, "mri", "synthesize", a.run_dir, "--landmarks", a.landmarks,
                         "--scan-type", "cine", "--voxel", "1mm", "--thickness", thickness,
                         "--fov", "80mm", "--frames", "30", "--snr", "20", "--seed", str(seed),
                         "-o", f"{tmp}/cine"])
            cine = run([BIN, "mri", "cine", "--landmarks", a.landmarks, "-o", f"{tmp}/measured", "-q"]
                       + [x for item in at for x in ("--at", item)])
            report = json.load(open(f"{tmp}/measured/cine.json"))
            per_seed.append({"seed": seed, "synthesize_s": round(synth, 1), "cine_s": round(cine, 2),
                             "swaps": sum(s["swaps"] for s in report["scans"].values()),
                             "landmarks": area_errors(f"{tmp}/measured", analysis)})
            per_seed[-1]["against_slab_mean"] = area_errors(f"{tmp}/measured", slab)
        worst = {lm: max(s["landmarks"][lm]["worst_percent"] for s in per_seed)
                 for lm in per_seed[0]["landmarks"]}
        worst_slab = {lm: max(s["against_slab_mean"][lm]["worst_percent"] for s in per_seed)
                      for lm in per_seed[0]["landmarks"]}
        result["cine"][thickness] = {"worst_over_seeds_percent": worst,
                                     "worst_against_slab_mean_percent": worst_slab,
                                     "seeds": per_seed}

    synth = run([BIN, "mri", "synthesize", a.run_dir, "--landmarks", a.landmarks, "--case", a.case,
                 "--scan-type", "pc", "--voxel", "1.5mm", "--thickness", "6mm", "--fov", "120mm",
                 "--frames", "30", "--snr", "20", "--venc", "1.5m/s", "--rotate", "15",
                 "--at", "inlet,BCT,LCC,LSA,outlet", "-o", f"{tmp}/pc"])
    inflow = run([BIN, "mri", "inflow", a.case, "--inlet", f"{tmp}/pc/inlet", "--landmarks",
                  f"{tmp}/pc/landmarks.json", "--pressure", "126.4/60/86.1mmHg", "-o", f"{tmp}/case", "-q"]
                 + [x for f in ("BCT", "LCC", "LSA", "outlet") for x in ("--outlet", f"{f}={tmp}/pc/{f}")])
    measured = json.load(open(f"{tmp}/case/mri_inflow.json"))
    cycles = json.load(open(os.path.join(a.run_dir, "cycles.json")))["cycles"][-1]
    faces = {}
    for r in rows(os.path.join(a.run_dir, "faces.csv")):
        if cycles["t_begin_s"] < float(r["time_s"]) <= cycles["t_end_s"]:
            faces.setdefault(r["face"], []).append(float(r["flow_m3_per_s"]) * 1e6)
    inlet = [-q for q in faces["inlet"]]
    out_total = sum(sum(faces[f]) / len(faces[f]) for f in ("BCT", "LCC", "LSA", "outlet"))
    scans = measured["scans"]
    result["phase_contrast"] = {
        "synthesize_s": round(synth, 1), "inflow_s": round(inflow, 2),
        "inflow_mean_mL_per_s": {"run": round(sum(inlet) / len(inlet), 2),
                                 "mri": round(scans["inflow"]["mean_flow_mL_per_s"], 2)},
        "inflow_peak_mL_per_s": {"run": round(max(inlet), 1),
                                 "mri": round(max(scans["inflow"]["flow_mL_per_s"]), 1)},
        "splits_percent": {f: {"run": round(100 * sum(faces[f]) / len(faces[f]) / out_total, 2),
                               "mri": round(measured["case"]["splits_percent"][f], 2)}
                           for f in ("BCT", "LCC", "LSA", "outlet")},
        "outflow_over_inflow": round(measured["case"]["outflow_over_inflow"], 4)}
    print(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
