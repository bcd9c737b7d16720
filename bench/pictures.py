#!/usr/bin/env python3
"""`tearflow pictures` on the built-in dissection's rigid run; prints JSON.

usage: bench/pictures.py [--element-size 4.5] [--steps 40] [--every 2] [--keep DIR]

Builds the OR model (`geometry tbad`), runs examples/tbad-rigid/case.yaml on it for `steps`
steps of 5 ms saving every `every`-th, then times `tearflow pictures` (peak systole and
mid-diastole: streamlines from three views, the plane maps) and `pictures --animate` (every
saved frame's streamlines too), with their peak memory (GNU time), the mesh's size, the
pictures' counts from pictures.json and the animation's bytes against its PNG frames'.
Renders through its own virtual X server when DISPLAY is unset. One process at a time: run it
on a quiet machine.
"""
import argparse, json, os, re, subprocess

from timing import BIN, ROOT, or_model, timed, work_dir


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--element-size", default="4.5")
    ap.add_argument("--steps", type=int, default=40)
    ap.add_argument("--every", type=int, default=2)
    ap.add_argument("--keep")
    a = ap.parse_args()
    tmp = work_dir(a.keep, "pictures")
    model = or_model(tmp, a.element_size)
    case = open(os.path.join(ROOT, "examples", "tbad-rigid", "case.yaml")).read()
    case = case.replace("file: geometry/mesh.msh", "file: " + os.path.join(model, "mesh.msh"))
    case = re.sub(r"time: \{step: 0.005, cycles: 2,", "time: {step: 0.005, steps: %d," % a.steps,
                  case)
    case = re.sub(r"^output: .*$", "output: {directory: %s, every: %d}" % (
        os.path.join(tmp, "run"), a.every), case, flags=re.M)
    with open(os.path.join(tmp, "case.yaml"), "w") as f:
        f.write(case)
    run = os.path.join(tmp, "run")
    if not os.path.exists(os.path.join(run, "flow.pvd")):
        subprocess.run([BIN, "run", os.path.join(tmp, "case.yaml")], check=True,
                       stdout=subprocess.DEVNULL)
    out = {"element_size_mm": float(a.element_size), "steps": a.steps, "every": a.every}
    for name, extra in (("pictures", []), ("pictures_animate", ["--animate"])):
        folder = os.path.join(tmp, name)
        _, wall, peak = timed([BIN, "pictures", run, "--model", model, "-o", folder, "--quiet"]
                              + extra)
        listing = json.load(open(os.path.join(folder, "pictures.json")))
        pngs = sum(1 for _, _, files in os.walk(folder) for f in files if f.endswith(".png"))
        out[name] = {"wall_s": round(wall, 1), "peak_mb": round(peak), "png_files": pngs,
                     "frames": len(listing.get("frames", []))}
        animation = listing.get("animation")
        if animation:  # the APNG's size against its frames' (report/apng.hpp)
            frames = os.path.join(folder, "animation")
            out[name]["animation_bytes"] = os.path.getsize(
                os.path.join(folder, animation["file"]))
            out[name]["animation_frames_bytes"] = sum(
                os.path.getsize(os.path.join(frames, f)) for f in os.listdir(frames))
    text = subprocess.run([BIN, "geometry", "report", model, "--no-png"], check=True,
                          capture_output=True, text=True).stdout
    tets = re.search(r"fluid\s+(\d+) tets", text)
    out["fluid_tets"] = int(tets.group(1)) if tets else None
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
