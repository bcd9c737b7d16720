"""What the benchmarks share: the tearflow binary and a command's wall time and peak memory."""
import os, re, subprocess, time

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
