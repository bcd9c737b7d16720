#!/usr/bin/env python3
"""`tearflow geometry labels` on the built-in dissection voxelized; prints JSON.

usage: bench/geometry_labels.py [--spacing 1,0.7] [--element-size 3] [--keep DIR]

Builds the OR model (`geometry tbad`, 3 mm), voxelizes it at each spacing in an oblique image
(rotated 20, -15, 30 degrees), rebuilds it with `geometry labels`, and reports per spacing the
image's size, the stages' times as the command prints them (fields, caps and landmarks,
meshing), the whole command's wall time and peak memory (GNU time), the mesh's tet counts and
the tears as found. One process at a time: run it on a quiet machine.
"""
import argparse, json, os, re, subprocess

from timing import BIN, or_model, timed, work_dir


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--spacing", default="1,0.7")
    ap.add_argument("--element-size", default="3")
    ap.add_argument("--keep")
    a = ap.parse_args()
    tmp = work_dir(a.keep, "labels")
    model = or_model(tmp)
    out = {"element_size_mm": float(a.element_size), "runs": []}
    for s in a.spacing.split(","):
        scan = os.path.join(tmp, f"or_{s}mm.nii.gz")
        vox = subprocess.run([BIN, "geometry", "voxelize", model, "-o", scan, "--spacing", s,
                              "--rotate", "20,-15,30"], check=True, capture_output=True, text=True)
        size = re.search(r"(\d+) x (\d+) x (\d+) voxels", vox.stdout).groups()
        text, wall, peak = timed([BIN, "geometry", "labels", scan, "--element-size",
                                  a.element_size, "-o", os.path.join(tmp, f"rebuilt_{s}")])
        stages = re.search(r"fields ([\d.]+) s, landmarks ([\d.]+) s, meshing ([\d.]+) s", text)
        tets = re.search(r"(\d+) nodes, (\d+) fluid and (\d+) wall tets", text)
        tears = dict((n, float(v)) for n, v in re.findall(r" (\w+) ([\d.]+) mm\^2", text.split("tears:")[1].splitlines()[0]))
        out["runs"].append({
            "spacing_mm": float(s), "image_voxels": [int(x) for x in size],
            "fields_s": float(stages.group(1)), "landmarks_s": float(stages.group(2)),
            "meshing_s": float(stages.group(3)), "wall_s": round(wall, 1),
            "peak_mb": round(peak), "nodes": int(tets.group(1)),
            "fluid_tets": int(tets.group(2)), "wall_tets": int(tets.group(3)),
            "tears_mm2": tears})
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
