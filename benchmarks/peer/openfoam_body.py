#!/usr/bin/python3
"""Peer run on a body grid: OpenFOAM's simpleFoam (k-omega SST) on exactly Narwhal's
grid (exported with `narwhal grid --openfoam`), beside Narwhal on the same case.

The OpenFOAM case (schemes, boundary conditions, forces) is validation/harness/openfoam.py's,
the one the spheroid rung runs; both codes report the force coefficient on 1/2 U^2 A_ref.
A code's time to its answer is the wall time at the first iteration after which its
drag stays within `--steady` (0.1 %) of its own final value; each code runs until its
forces have long settled, and the final values are compared side by side.

OpenFOAM (Debian package `openfoam`) is installed by ci/nightly only, never by CI.

  benchmarks/peer/openfoam_body.py CASE.toml [--set key=value ...] [--narwhal build/solver/narwhal]
      [--out DIR] [--iterations N] [--ranks 2] [--repeat 3]
"""
import argparse
import json
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path
from types import SimpleNamespace

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "validation"))
from harness import openfoam  # noqa: E402  (the peer case: one place, shared with the harness)
from harness.runner import effective_input  # noqa: E402


def foam_history(d, s):
    """(iteration, wall seconds, drag coefficient along x of the grid) of the OpenFOAM run."""
    return [(i, w, parts["total"]["cfx"]) for i, w, parts in openfoam.history(d, s)]


def narwhal_history(d):
    lines = [l for l in (d / "history.csv").read_text().splitlines() if not l.startswith("#")]
    head = lines[0].split(",")
    iw, ic = head.index("wall_s"), head.index("body_cfx")
    return [(int(r.split(",")[0]), float(r.split(",")[iw]), float(r.split(",")[ic])) for r in lines[1:]]


def time_to_steady(rows, tol):
    """(iteration, wall s) of the first row after which the drag stays within tol of the last."""
    final = rows[-1][2]
    for n in range(len(rows)):
        if all(abs(r[2] - final) <= tol * abs(final) for r in rows[n:]):
            return rows[n][0], rows[n][1], final
    return rows[-1][0], rows[-1][1], final


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case")
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--narwhal", default=str(ROOT / "build" / "solver" / "narwhal"))
    ap.add_argument("--out", default=str(ROOT / "reports" / "peer_body"))
    ap.add_argument("--iterations", type=int, default=3000, help="OpenFOAM iterations")
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--steady", type=float, default=1e-3)
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    overrides = dict(o.split("=", 1) for o in a.set)
    s = openfoam.case_settings(effective_input(SimpleNamespace(input=a.case, set=overrides)), a.case)
    sets = sum((["--set", x] for x in a.set), [])
    results = {"case": a.case, "set": a.set, "steady_tolerance": a.steady, "narwhal": [], "openfoam": []}
    for rep in range(a.repeat):
        nd = out / f"narwhal_{rep}"
        shutil.rmtree(nd, ignore_errors=True)
        launch = ["mpirun", "-np", str(a.ranks), "--oversubscribe"] if a.ranks > 1 else []
        t0 = time.monotonic()
        done = subprocess.run(launch + [a.narwhal, "run", a.case, "--out", str(nd)] + sets,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        if done.returncode not in (0, 1):  # 1: stopped at its limit; the drag history still tells
            sys.exit(f"narwhal exited with {done.returncode} (2: input error, 3: diverged); see {nd}")
        whole = time.monotonic() - t0
        it, wall, cd = time_to_steady(narwhal_history(nd), a.steady)
        results["narwhal"].append({"iterations_to_steady": it, "wall_s_to_steady": wall, "cd": cd, "process_s": whole})
        fd = out / f"openfoam_{rep}"
        shutil.rmtree(fd, ignore_errors=True)
        subprocess.run([a.narwhal, "grid", a.case, "--out", str(fd / "narwhal_grid"), "--openfoam", str(fd)] + sets,
                       check=True, stdout=subprocess.DEVNULL)
        openfoam.write_case(fd, s, a.iterations)
        openfoam.run(fd, a.ranks)
        it, wall, cd = time_to_steady(foam_history(fd, s), a.steady)
        results["openfoam"].append({"iterations_to_steady": it, "wall_s_to_steady": wall, "cd": cd})
        print(json.dumps({"narwhal": results["narwhal"][-1], "openfoam": results["openfoam"][-1]}), flush=True)
    for code in ("narwhal", "openfoam"):
        results[f"{code}_median_wall_s_to_steady"] = statistics.median(r["wall_s_to_steady"] for r in results[code])
    results["speed_ratio"] = results["openfoam_median_wall_s_to_steady"] / results["narwhal_median_wall_s_to_steady"]
    (out / "peer_body.json").write_text(json.dumps(results, indent=1) + "\n")
    print(json.dumps({k: v for k, v in results.items() if k not in ("narwhal", "openfoam")}, indent=1))


if __name__ == "__main__":
    main()
