#!/usr/bin/env python3
"""4D-flow MRI end to end at the reference study's size; prints JSON.

usage: bench/mri_pipeline.py [--size 220,156,56] [--frames 20] [--format dicom] [--keep DIR]
Synthesizes the analytic pulsatile pipe (`tearflow mri synthesize`: R 10 mm, 1.5 mm voxels,
SNR 20, venc 1.5 m/s, a 0.05 m/s linear + quadratic background, grid rotated 15 degrees,
static tissue out to 80 mm), then times `tearflow mri flow` on it: read every file, unwrap,
fit and remove the background, measure the two landmark planes, write the tables. The
synthesis is timed apart (it is not part of processing a scan). Reports the wall time and
peak memory of `mri flow`, its phases (mri.json) and the worst frame flow error against the
exact window-mean flow.
"""
import argparse, csv, json, os, resource, subprocess, tempfile, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "tearflow")


def timed(cmd):
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    return wall, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0


def read_table(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--size", default="220,156,56")
    ap.add_argument("--frames", type=int, default=20)
    ap.add_argument("--format", default="dicom", choices=["dicom", "dicom-rescaled", "nifti", "mha"])
    ap.add_argument("--keep", help="keep the data in this folder")
    args = ap.parse_args()
    tmp = args.keep or tempfile.mkdtemp(prefix="tearflow-bench-mri-")
    scan, flow = os.path.join(tmp, "scan"), os.path.join(tmp, "flow")
    synth_s, _ = timed([BIN, "mri", "synthesize", "-o", scan, "--size", args.size, "--frames",
                        str(args.frames), "--voxel", "1.5mm", "--radius", "10mm", "--tissue", "80mm",
                        "--snr", "20", "--venc", "1.5m/s", "--background", "0.05m/s",
                        "--rotate", "15", "--format", args.format])
    files = sum(len(fs) for _, _, fs in os.walk(os.path.join(scan, "images")))
    flow_s, peak_mb = timed([BIN, "mri", "flow", os.path.join(scan, "images"), "--landmarks",
                             os.path.join(scan, "landmarks.json"), "-o", flow, "-q"])
    report = json.load(open(os.path.join(flow, "mri.json")))
    exact = read_table(os.path.join(scan, "exact", "flow.csv"))
    measured = read_table(os.path.join(flow, "flow.csv"))
    worst = max(abs(m - e) / e for k in ("inlet_mL_per_s", "outlet_mL_per_s")
                for m, e in zip(measured[k], exact[k]))
    nx, ny, nz = (int(v) for v in args.size.split(","))
    print(json.dumps({
        "voxels": [nx, ny, nz], "frames": args.frames, "format": args.format, "files": files,
        "cores": os.cpu_count(),
        "synthesize_s": round(synth_s, 2),
        "mri_flow_wall_s": round(flow_s, 2),
        "mri_flow_peak_memory_MB": round(peak_mb, 1),
        "phases_s": {k: round(report[k], 2) for k in ("read_s", "unwrap_s", "background_s", "planes_s")},
        "static_voxels": report["background"]["static_voxels"],
        "unwrapped_values": report["unwrap"]["values_unwrapped"] if isinstance(report["unwrap"], dict) else None,
        "worst_frame_flow_error_percent": round(100 * worst, 3),
        "data": tmp if args.keep else None,
    }, indent=2))
    if not args.keep:
        subprocess.run(["rm", "-rf", tmp], check=True)


if __name__ == "__main__":
    main()
