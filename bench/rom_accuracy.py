#!/usr/bin/env python3
"""The reduced-order model against held-out 3D variants of a study; prints JSON.

usage: bench/rom_accuracy.py STUDY_OUTPUT [STUDY_OUTPUT ...] [--also STUDY_OUTPUT]

For each finished study output folder with the variants OR, EN and EX (or those of them it holds;
a calibration or prediction that needs a missing one is left out) (the main job's
results/tbad-demo, its rigid form, or the same at another element size), and for each kind of
run it holds (`run`: the study's walls; `rigid`: compare_rigid's rigid counterparts), calibrates
the model on OR's model directory (copied, so the study is not touched) with
  OR alone, OR + EX, OR + EN
and predicts each variant left out with its own case (its tuned outlets) and OR's geometry with
the tear resized (as `rom sweep` does), comparing with the variant's 3D analysis: FR_FL per
station and the peak-systolic dP per station. `pass` applies the issue's criterion: FR_FL within
5 points at every station and dP within 3 mmHg or 20 % at every station.

--also names a study of other tear sizes of the same geometry (any variant names, e.g.
study-rigid-3mm-n6-mid.yaml's EN120 and EX120): each of its variants is predicted too, from
every calibration of the (first) study above, its tears resized to the areas its own
geometry/landmarks.json declares.
"""
import argparse, json, os, shutil, subprocess, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "tearflow")
AREA = {"EN": ("--entry-tear-area", "62"), "EX": ("--exit-tear-area", "61")}


def stations(metrics):
    st = json.load(open(metrics))["stations"]
    keys = sorted(st, key=int)
    return ([st[k]["FR_FL_percent"] for k in keys],
            [st[k]["dP_TL_minus_FL_peak_systole_mmHg"] for k in keys])


def case_of(study, variant, kind):
    return (os.path.join(study, variant, "run", "tuned.yaml") if kind == "run"
            else os.path.join(study, variant, "rigid.yaml"))


def declared_areas(study, variant):
    """`--tear-area NAME=MM2` for each tear of a variant's own model."""
    lm = json.load(open(os.path.join(study, variant, "geometry", "landmarks.json")))
    args = []
    for t in lm.get("tears", []):
        args += ["--tear-area", f"{t['name']}={t['area']:g}"]
    return args


def arguments():
    ap = argparse.ArgumentParser(
        description="The reduced-order model against held-out 3D variants of a study (JSON).")
    ap.add_argument("studies", nargs="+", metavar="STUDY_OUTPUT",
                    help="a finished study's output folder (variants OR, EN, EX)")
    ap.add_argument("--also", metavar="STUDY_OUTPUT",
                    help="a study of other tear sizes of the first study's geometry")
    return ap.parse_args()


def main():
    out = []
    args = arguments()
    argv, also = args.studies, args.also
    for study in argv:
        tmp = tempfile.mkdtemp(prefix="tearflow-rom-accuracy-")
        model = os.path.join(tmp, "OR")
        os.makedirs(model)
        for f in ("mesh.msh", "landmarks.json"):
            shutil.copy(os.path.join(study, "OR", "geometry", f), model)
        for kind in ("run", "rigid"):
            if not os.path.isdir(os.path.join(study, "OR", kind, "analysis")):
                continue
            have = [v for v in ("OR", "EN", "EX")
                    if os.path.isdir(os.path.join(study, v, kind, "analysis"))]
            for calibrated_on in (["OR"], ["OR", "EX"], ["OR", "EN"]):
                if any(v not in have for v in calibrated_on):
                    continue
                cmd = [BIN, "rom", "calibrate", "-q", model]
                for v in calibrated_on:
                    cmd += ["--run", os.path.join(study, v, kind), "--case", case_of(study, v, kind),
                            "--run-model", os.path.join(study, v, "geometry")]
                if os.path.exists(os.path.join(model, "rom", "calibration.json")):
                    os.remove(os.path.join(model, "rom", "calibration.json"))
                subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
                targets = [(study, v, AREA[v]) for v in ("EN", "EX")
                           if v not in calibrated_on and v in have]
                if also and study == argv[0]:
                    targets += [(also, v, declared_areas(also, v)) for v in sorted(os.listdir(also))
                                if os.path.isdir(os.path.join(also, v, kind, "analysis"))]
                for source, v, area in targets:
                    pred = os.path.join(tmp, f"{kind}-{'-'.join(calibrated_on)}-"
                                        f"{os.path.basename(os.path.normpath(source))}-{v}")
                    subprocess.run([BIN, "rom", "predict", "-q", model, "--case",
                                    case_of(source, v, kind), *area, "-o", pred], check=True)
                    fr, dp = stations(os.path.join(pred, "analysis", "metrics.json"))
                    fr3, dp3 = stations(os.path.join(source, v, kind, "analysis", "metrics.json"))
                    fr_err = max(abs(a - b) for a, b in zip(fr, fr3))
                    dp_ok = all(abs(a - b) <= max(3.0, 0.2 * abs(b)) for a, b in zip(dp, dp3))
                    out.append({"study": source, "walls": kind, "calibrated_on": calibrated_on,
                                "predicted": v, "FR_FL_rom": [round(x, 1) for x in fr],
                                "FR_FL_3d": [round(x, 1) for x in fr3],
                                "FR_FL_max_error_points": round(fr_err, 1),
                                "dP_peak_systole_rom_mmHg": [round(x, 1) for x in dp],
                                "dP_peak_systole_3d_mmHg": [round(x, 1) for x in dp3],
                                "pass": fr_err <= 5.0 and dp_ok})
        shutil.rmtree(tmp)
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
