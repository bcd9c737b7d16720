"""Runs `tearflow run CASE` (optionally under mpirun) and summarises its progress lines.

Shared by the solver benchmarks: per step the program prints Newton and Krylov iterations,
seconds per step and assembly seconds; the first timed step is start-up and is dropped when
more than two were run. Peak memory from /usr/bin/time (max over ranks)."""
import os, re, subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("TEARFLOW", os.path.join(ROOT, "build", "tearflow"))
LINE = re.compile(r"step\s+(\d+)/\d+.*Newton (\d+) .*KSP\s+(\d+)\s+([\d.]+) s/step "
                  r"\(assembly ([\d.]+) s\)")


def edit_case(text, mesh=None, step=None, time_scale=None, drop_time_scale=False, rtol=None,
              max_cycles=None, output=None):
    """A case file's text (flow-style mappings, as examples/tbad-study's) with keys replaced:
    the mesh file, time.step, fluid.stabilization_time_scale (set, or dropped), newton.rtol,
    time.periodicity.max_cycles, and the output mapping's contents. The benchmarks' one edit."""
    if drop_time_scale:
        text = re.sub(r",? *stabilization_time_scale: [^,}]*", "", text)
    if time_scale:
        text = re.sub(r"fluid: \{", "fluid: {stabilization_time_scale: %r, " % time_scale, text)
    if mesh:
        text = re.sub(r"mesh: \{file: [^,]*,", "mesh: {file: " + mesh + ",", text)
    if step:
        text = re.sub(r"time: \{step: [^,]*,", "time: {step: %r," % step, text)
    if max_cycles:
        text = re.sub(r"max_cycles: \d+", "max_cycles: %d" % max_cycles, text)
    if rtol:
        text = re.sub(r"rtol: [^,}]*", "rtol: %r" % rtol, text)
    if output is not None:
        text = re.sub(r"output: \{[^}]*\}", "output: {" + output + "}", text)
    return text


def run_case(case, ranks, out_dir, steps=None, cwd=None, extra=()):
    cmd = [BIN, "run", case, "-o", out_dir] + (["--steps", str(steps)] if steps else []) + list(extra)
    if ranks > 1:
        cmd = ["mpirun", "-n", str(ranks)] + cmd
    cmd = ["/usr/bin/time", "-f", "MAXRSS %M"] + cmd
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    out = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=cwd)
    if out.returncode != 0:
        return {"ranks": ranks, "error": out.stdout[-2000:] + out.stderr[-2000:]}
    rows = [tuple(map(float, m.groups())) for m in LINE.finditer(out.stdout)]
    rows = rows[1:] if len(rows) > 2 else rows
    mesh_line = re.search(r"mesh: (\d+) nodes, (\d+) tets", out.stdout)
    rss = max(int(x) for x in re.findall(r"MAXRSS (\d+)", out.stderr))
    n = len(rows)
    newton = sum(r[1] for r in rows)
    return {
        "ranks": ranks, "nodes": int(mesh_line.group(1)), "tets": int(mesh_line.group(2)),
        "steps_timed": n,
        "seconds_per_step": sum(r[3] for r in rows) / n,
        "seconds_per_newton_iteration": sum(r[3] for r in rows) / newton,
        "assembly_seconds_per_step": sum(r[4] for r in rows) / n,
        "solve_seconds_per_step": sum(r[3] - r[4] for r in rows) / n,
        "newton_per_step": newton / n,
        "ksp_per_step": sum(r[2] for r in rows) / n,
        "peak_rss_MiB_one_process_max": rss / 1024.0,
    }
