#!/usr/bin/env python3
"""Projects the FSI time per step to many ranks from PETSc's -log_view (issue 23, item 5);
prints JSON.

usage: bench/scaling_model.py LOG [--log1 LOG] [--ranks 16 48 128]
                              [--latency 2e-6] [--bandwidth 1e10] [--allreduce 3e-6]
                              [--neighbours 12]
  LOG:    -log_view of a run on R >= 2 ranks (PETSC_OPTIONS="-log_view :file" on any
          `tearflow run`, e.g. bench/fsi_cycle.py's); its steps are the SNESSolve count.
  --log1: the same steps on 1 rank: the direct solver's measured speedup from 1 to R.

The model, per time step (every term from the log unless said):
  T(P) = T_local (R / P) b  +  T_direct(P)  +  m(P) (latency + s(P) / bandwidth)
         +  n_red log2(P) allreduce
  T_local:  SNESSolve's time less the direct solver's (MUMPS: MatLUFactorSym/Num, MatSolve)
            and less the measured communication estimate: assembly, Krylov vectors, AMG
            V-cycles, sparse products. It divides by P: the work is per node and the
            partitioner's share is even; b is the largest max/min time ratio over the
            residual and Jacobian evaluations (load balance), held at P.
  T_direct: the wall block's factorization and solves; scaled per doubling of P by the
            speedup measured from 1 to R ranks (--log1), else by sqrt(2) per doubling
            (a direct solver's distributed phase scales poorly).
  m(P):     point-to-point messages per rank and step: the log's count per rank at R, times
            min(P - 1, neighbours) / (R - 1) (a rank of a 3D partition has about 12
            neighbours); s(P) the mean message length, shrinking with the partition's
            surface, (R / P)^(2/3).
  n_red:    global reductions per step (dot products and norms of GMRES and CG, AMG's setup),
            each a log2(P)-deep tree of --allreduce seconds.
Assumptions, stated because the log cannot show them: Krylov and Newton iterations per step
do not change with P (the wall block is solved exactly; BoomerAMG's V-cycle rate is nearly
independent of P); the network is an InfiniBand-class one (2 us latency, 10 GB/s per rank);
one rank per core with the memory bandwidth per core of the measuring machine; no I/O.
"""
import argparse, json, math, re


def read_log(path):
    """Per event: count, max time [s], max/min time ratio, messages, mean length, reductions."""
    events, ranks = {}, None
    for line in open(path):
        m = re.search(r"with (\d+) processors?", line)
        if m and ranks is None:
            ranks = int(m.group(1))
        f = line.split()
        # name count ratio time ratio flop ratio mess avglen reduct %T ...
        if len(f) >= 10 and re.fullmatch(r"\d+", f[1] or "") and not line.startswith(" "):
            try:
                events[f[0]] = {"count": int(f[1]), "time": float(f[3]), "ratio": float(f[4]),
                                "messages": float(f[7]), "length": float(f[8]),
                                "reductions": float(f[9])}
            except ValueError:
                pass
    return events, ranks


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("log")
    ap.add_argument("--log1")
    ap.add_argument("--ranks", type=int, nargs="+", default=[16, 48, 128])
    ap.add_argument("--latency", type=float, default=2e-6)
    ap.add_argument("--bandwidth", type=float, default=1e10)
    ap.add_argument("--allreduce", type=float, default=3e-6)
    ap.add_argument("--neighbours", type=int, default=12)
    a = ap.parse_args()
    ev, R = read_log(a.log)
    steps = ev["SNESSolve"]["count"]
    t = lambda name, e=ev: e.get(name, {"time": 0.0})["time"]
    direct = t("MatLUFactorSym") + t("MatLUFactorNum") + t("MatSolve")
    total = t("SNESSolve")
    # messages and reductions as PETSc counts them: summed over ranks in the event lines
    messages = ev["SNESSolve"]["messages"] / R / steps
    length = ev["SNESSolve"]["length"]
    reductions = ev["SNESSolve"]["reductions"] / steps
    comm_R = messages * (a.latency + length / a.bandwidth) + reductions * a.allreduce * math.log2(R)
    local = (total - direct) / steps - comm_R
    balance = max(ev[n]["ratio"] for n in ("SNESFunctionEval", "SNESJacobianEval") if n in ev)
    if a.log1:
        ev1, _ = read_log(a.log1)
        d1 = (t("MatLUFactorSym", ev1) + t("MatLUFactorNum", ev1) + t("MatSolve", ev1)) / \
            ev1["SNESSolve"]["count"]
        per_doubling = (d1 / (direct / steps)) ** (1.0 / math.log2(R)) if direct > 0 else 1.0
    else:
        per_doubling = math.sqrt(2.0)
    rows = []
    for P in [R] + a.ranks:
        d = direct / steps / per_doubling ** math.log2(P / R)
        m = messages * min(P - 1, a.neighbours) / max(R - 1, 1)
        s = length * (R / P) ** (2.0 / 3.0)
        comm = m * (a.latency + s / a.bandwidth) + reductions * a.allreduce * math.log2(P)
        loc = local * R / P * (balance if P > R else 1.0)
        rows.append({"ranks": P, "seconds_per_step": loc + d + comm, "local": loc,
                     "direct": d, "communication": comm,
                     "parallel_efficiency_vs_R": (total / steps) * R / P / (loc + d + comm)})
    print(json.dumps({"log": a.log, "measured_ranks": R, "steps": steps,
                      "measured_seconds_per_step": total / steps,
                      "direct_seconds_per_step": direct / steps,
                      "direct_speedup_per_doubling": per_doubling,
                      "messages_per_rank_per_step": messages, "mean_message_bytes": length,
                      "reductions_per_step": reductions, "load_balance_max_over_min": balance,
                      "assumptions": {"latency_s": a.latency, "bandwidth_B_per_s": a.bandwidth,
                                      "allreduce_hop_s": a.allreduce,
                                      "neighbours": a.neighbours},
                      "projection": rows}, indent=2))


if __name__ == "__main__":
    main()
