#!/usr/bin/python3
"""MPI scaling of Narwhal (issue #6): a measured strong-scaling step from 1 to 2 ranks on a
case of more than a million cells, and a weak-scaling estimate for 64-1024 ranks from
measured halo volumes and message counts and a stated network model.

Strong scaling. The laminar square duct (validation/cases/square_duct_laminar) on a
64 x 128 x 128 box (1 048 576 cells), 3-level V-cycles, 4 SGS pairs per Newton iteration (the
plates' setting; the duct's own 20 would only stretch the sweeps), a fixed number of cycles; one rank
runs the case's single block, two ranks the two pieces the balancer cuts. Time: the
solver loop's wall time from run.json (set-up and output excluded; the slower rank's),
repetitions interleaved (1, 2, 1, 2, ...) because the machine drifts; efficiency
E = median T1 / (2 median T2).

Weak scaling. Each rank keeps a cube of n^3 cells (n = 64 by default). The balancer's
blocks and the halo each rank sends per ghost fill come from `narwhal partition` on boxes
of P = 8, 27 and 64 such cubes (interior ranks appear from P = 27 on; a rank's halo and
its neighbour count do not grow beyond that with P). The time per multigrid cycle at P
ranks is modelled as
    T(P) = T_compute(n^3) + N_fill * (m_fill * alpha + b_fill / beta) + N_red * ceil(log2 P) * alpha
with T_compute the measured 1-rank cycle time scaled to n^3 cells, N_fill the ghost fills
and halo exchanges per cycle (counted from the code path below), m_fill and b_fill the
largest rank's messages and bytes per fill (measured), N_red the global reductions per
cycle, and a network of alpha = 2 us latency and beta = 10 GB/s per link (a 100 Gb/s
InfiniBand or Omni-Path class fabric under MPI; both stated, not measured here).

Usage: benchmarks/mpi_scaling.py [--narwhal build/solver/narwhal] [--repeats 3]
       [--cycles 6] [--out reports/mpi_scaling.json]
Needs a NARWHAL_MPI build and mpirun; runs as root are allowed through OMPI's variables.
"""
import argparse
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DUCT = ROOT / "validation" / "cases" / "square_duct_laminar" / "duct.toml"

ALPHA = 2.0e-6   # s per message (stated network model)
BETA = 10.0e9    # bytes per second per link (stated network model)


def env():
    e = dict(os.environ)
    if os.geteuid() == 0:
        e.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
        e.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    return e


def box_settings(nx, ny, nz, lx=2.0):
    return ["--set", f"grid.x=[0.0, {lx}, {nx}]", "--set", f"grid.y=[-1.0, 1.0, {ny}]",
            "--set", f"grid.z=[-1.0, 1.0, {nz}]"]


def run_case(narwhal, ranks, cycles, out):
    cmd = [] if ranks == 1 else [shutil.which("mpirun"), "-n", str(ranks), "--oversubscribe"]
    cmd += [str(narwhal), "run", str(DUCT), "-o", str(out), "--max-iterations", str(cycles),
            "--set", "solver.multigrid_levels=3", "--set", 'solver.multigrid_cycle="V"',
            "--set", "solver.sgs_iterations=4", "--set", "output.restart_interval=0", *box_settings(64, 128, 128)]
    p = subprocess.run(cmd, capture_output=True, text=True, env=env())
    if p.returncode not in (0, 1):
        sys.exit(f"mpi_scaling: {' '.join(cmd)} failed ({p.returncode}):\n{p.stdout}\n{p.stderr}")
    with open(out / "run.json") as f:
        data = json.load(f)
    return {"ranks": ranks, "wall_seconds": data["wall_seconds"], "iterations": data["iterations"],
            "cells": data["cells"], "blocks": data["blocks"]}


def partition(narwhal, n, per_side):
    """Halo statistics of a box of per_side^3 cubes of n^3 cells on per_side^3 ranks."""
    ranks = per_side ** 3
    cmd = [str(narwhal), "partition", str(DUCT), "-n", str(ranks), "--set", "solver.multigrid_levels=3",
           *box_settings(n * per_side, n * per_side, n * per_side, lx=2.0)]
    p = subprocess.run(cmd, capture_output=True, text=True, env=env(), check=True)
    rows = re.findall(r"rank\s+(\d+):\s+(\d+) block\(s\),\s+(\d+) cells, sends\s+(\d+) halo cells in\s+(\d+) message",
                      p.stdout)
    if len(rows) != ranks:
        sys.exit(f"mpi_scaling: cannot read `{' '.join(cmd)}`:\n{p.stdout}")
    cells = [int(r[2]) for r in rows]
    halo = [int(r[3]) for r in rows]
    peers = [int(r[4]) for r in rows]
    head = re.search(r"(\d+) cells in (\d+) block\(s\) over (\d+) rank\(s\), load imbalance ([0-9.]+) %", p.stdout)
    return {"ranks": ranks, "cells_per_rank_target": n ** 3, "blocks": int(head.group(2)),
            "imbalance_percent": float(head.group(4)), "max_cells": max(cells), "max_halo_cells": max(halo),
            "mean_halo_cells": statistics.mean(halo), "max_peers": max(peers)}


# Per multigrid V(1,1) cycle on L levels, with s SGS pairs per Newton iteration: every
# smoothing iteration fills the ghosts once (residual) and exchanges the SGS corrections
# twice per pair; restriction evaluates one residual per level, prolongation fills the
# correction's ghosts; a fill exchanges Q and nu (two arrays). Counted from
# multigrid/fas.cpp and implicit/newton.cpp.
def exchanges_per_cycle(levels=3, sgs_pairs=4, pre=1, post=1, coarse=2):  # the strong-scaling run's settings
    smooth = (levels - 1) * (pre + post) + coarse
    fills = 2 * (smooth + 1 + (levels - 1) * 2) + (levels - 1)  # Q+nu per residual; corrections
    sgs = smooth * 2 * sgs_pairs
    reductions = smooth + 1 + (levels - 1)  # residual norms (one vector reduction each)
    return fills, sgs, reductions


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--narwhal", default=str(ROOT / "build" / "solver" / "narwhal"))
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--cycles", type=int, default=6)
    ap.add_argument("--cube", type=int, default=64, help="cells per rank and direction (weak scaling)")
    ap.add_argument("--partition-cube", type=int, default=32,
                    help="cube size the halos are measured on (scaled by (cube / this)^2)")
    ap.add_argument("--out", default=str(ROOT / "reports" / "mpi_scaling.json"))
    ap.add_argument("--skip-strong", action="store_true")
    args = ap.parse_args()
    narwhal = Path(args.narwhal)
    if "MPI" not in subprocess.run([str(narwhal), "--version"], capture_output=True, text=True).stdout.replace(
            "no MPI", ""):
        sys.exit("mpi_scaling: this narwhal was built without MPI (configure with -DNARWHAL_MPI=ON)")

    result = {"network_model": {"alpha_s": ALPHA, "beta_bytes_per_s": BETA}}
    if not args.skip_strong:
        runs = []
        with tempfile.TemporaryDirectory() as tmp:
            for rep in range(args.repeats):
                for ranks in (1, 2):
                    r = run_case(narwhal, ranks, args.cycles, Path(tmp) / f"r{ranks}_{rep}")
                    runs.append(r)
                    print(f"  {ranks} rank(s): {r['wall_seconds']:.2f} s for {r['iterations']} cycles", flush=True)
        t1 = statistics.median(r["wall_seconds"] for r in runs if r["ranks"] == 1)
        t2 = statistics.median(r["wall_seconds"] for r in runs if r["ranks"] == 2)
        pairs = [a["wall_seconds"] / (2 * b["wall_seconds"])
                 for a, b in zip([r for r in runs if r["ranks"] == 1], [r for r in runs if r["ranks"] == 2])]
        result["strong"] = {"cells": runs[0]["cells"], "cycles": args.cycles, "runs": runs, "median_t1": t1,
                            "median_t2": t2, "speedup": t1 / t2, "efficiency": t1 / (2 * t2),
                            "efficiency_per_pair": pairs}
        print(f"strong scaling, {runs[0]['cells']} cells: T1 {t1:.2f} s, T2 {t2:.2f} s (medians), "
              f"speed-up {t1 / t2:.3f}, efficiency {100 * t1 / (2 * t2):.1f} % "
              f"(pairs: {', '.join(f'{100 * p:.1f}' for p in pairs)} %)")

    n, m = args.cube, args.partition_cube
    weak = [partition(narwhal, m, s) for s in (2, 3, 4)]
    result["weak_partitions"] = weak
    worst = max(weak, key=lambda w: w["max_halo_cells"])
    fills, sgs, reductions = exchanges_per_cycle()
    # Bytes per fill: Q (4 doubles) + nu (1 double) per halo cell; SGS exchanges: the
    # first face layer only (about a quarter of a fill's halo) of 4 doubles.
    halo = worst["max_halo_cells"] * (n / m) ** 2  # a face's cells grow with its area
    peers = worst["max_peers"]
    fill_bytes = halo * 8 * 5
    fill_messages = 4 * peers * 2  # (d, depth) steps talk to the neighbours of direction d; two rounds; Q and nu
    sgs_bytes = halo / 4 * 8 * 4
    sgs_messages = peers
    t_cell = None
    if "strong" in result:
        t_cell = result["strong"]["median_t1"] / args.cycles / result["strong"]["cells"]
    model = []
    for P in (64, 128, 256, 512, 1024):
        comm = (fills / 2 * (fill_messages * ALPHA + fill_bytes / BETA) + sgs * (sgs_messages * ALPHA + sgs_bytes / BETA)
                + reductions * math.ceil(math.log2(P)) * 2 * ALPHA)
        row = {"ranks": P, "cells": P * n ** 3, "comm_seconds_per_cycle": comm}
        if t_cell:
            comp = t_cell * n ** 3
            row.update(compute_seconds_per_cycle=comp, efficiency=comp / (comp + comm))
        model.append(row)
    result["weak_model"] = {"cube": n, "measured_on_cube": m, "halo_cells_per_fill": halo, "peers": peers, "fills_per_cycle": fills,
                            "sgs_exchanges_per_cycle": sgs, "reductions_per_cycle": reductions, "rows": model}
    for w in weak:
        print(f"  partition {w['ranks']:4d} ranks of {m}^3: {w['blocks']} blocks, imbalance {w['imbalance_percent']:.2f} %, "
              f"largest halo {w['max_halo_cells']} cells/fill ({100 * w['max_halo_cells'] / m ** 3:.1f} %), "
              f"up to {w['max_peers']} peers")
    for r in model:
        extra = f", efficiency {100 * r['efficiency']:.2f} %" if "efficiency" in r else ""
        print(f"  weak model {r['ranks']:5d} ranks ({r['cells'] / 1e6:.0f} M cells): communication "
              f"{1e3 * r['comm_seconds_per_cycle']:.2f} ms per cycle{extra}")
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    with open(args.out, "w") as f:
        json.dump(result, f, indent=1)
    print(f"mpi_scaling: wrote {args.out}")


if __name__ == "__main__":
    main()
