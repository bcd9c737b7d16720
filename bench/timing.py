"""What the benchmarks share: the tearflow binary and a command's wall time and peak memory."""
import os, re, subprocess, tempfile, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "tearflow")


def timed(cmd):
    """Runs cmd under GNU time: (its stdout, wall time [s], peak memory [MB])."""
    t0 = time.perf_counter()
    p = subprocess.run(["/usr/bin/time", "-f", "peak_kb=%M"] + cmd, check=True,
                       capture_output=True, text=True)
    wall = time.perf_counter() - t0
    peak = int(re.search(r"peak_kb=(\d+)", p.stderr).group(1))
    return p.stdout, wall, peak / 1024.0


def work_dir(keep, name):
    """The benchmark's folder: --keep's (made if missing), else a fresh temporary one."""
    tmp = keep or tempfile.mkdtemp(prefix=f"tearflow-bench-{name}-")
    os.makedirs(tmp, exist_ok=True)
    return tmp


def or_model(tmp, element_size=None):
    """TMP/or: the built-in OR dissection (`geometry tbad`, its default size unless given),
    built once and kept for the next run with the same --keep."""
    model = os.path.join(tmp, "or")
    if not os.path.exists(os.path.join(model, "mesh.msh")):
        size = ["--element-size", str(element_size)] if element_size is not None else []
        subprocess.run([BIN, "geometry", "tbad"] + size + ["-o", model], check=True,
                       stdout=subprocess.DEVNULL)
    return model
