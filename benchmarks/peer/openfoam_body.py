#!/usr/bin/python3
"""Peer run on a body grid: OpenFOAM's simpleFoam (k-omega SST) on exactly Narwhal's
grid (exported with `narwhal grid --openfoam`), beside Narwhal on the same case.

The OpenFOAM case (schemes, boundary conditions, forces) is validation/harness/openfoam.py's,
the one the spheroid rung runs; both codes report the force coefficient on 1/2 U^2 A_ref.
Each code first runs well past its answer; the iteration after which its drag stays
within `--steady` (0.1 %) of its final value is where it has the answer. Each is then run
again from scratch, stopped at that iteration, `--repeat` times in alternation: the median
of those wall times (set-up included) is its time to the answer. peer_body.json in --out
records each finished run: rerun with the same arguments, the benchmark continues where it
stopped (a simpleFoam run on a 1 M-cell grid takes hours); the converging simpleFoam run
itself continues from its last write (every 50 iterations).

OpenFOAM (Debian package `openfoam`) is installed by ci/nightly only, never by CI.

  benchmarks/peer/openfoam_body.py CASE.toml [--set key=value ...] [--narwhal build/solver/narwhal]
      [--out DIR] [--iterations N] [--ranks 2] [--repeat 3]
      [--start-reynolds 1e4 --start-iterations 100]

simpleFoam diverges from the uniform stream on the SUBOFF grids (harness/openfoam.py,
StartStage): --start-reynolds runs its first --start-iterations at that Reynolds number,
then the case's; the time to the answer includes that stage.
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
CHECKPOINT = 50  # iterations between the converging simpleFoam run's writes
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


def resumed(path, identity):
    """The results so far of this same benchmark in --out (its runs already done), or a fresh
    record; results of another benchmark there are an error naming the first key that differs."""
    if not path.exists():
        return dict(identity)
    done = json.loads(path.read_text())
    for key, value in identity.items():
        if done.get(key) != value:
            sys.exit(f"{path}: holds another benchmark's results ({key}: {done.get(key)!r}, now {value!r}); "
                     "choose another --out or remove it")
    return done


def run_narwhal(a, sets, d, max_iterations=None):
    """One Narwhal run; the process's wall time (set-up included)."""
    shutil.rmtree(d, ignore_errors=True)
    launch = ["mpirun", "-np", str(a.ranks), "--oversubscribe"] if a.ranks > 1 else []
    limit = ["--max-iterations", str(max_iterations)] if max_iterations else []
    t0 = time.monotonic()
    done = subprocess.run(launch + [a.narwhal, "run", a.case, "--out", str(d)] + sets + limit,
                          stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    if done.returncode not in (0, 1):  # 1: stopped at its limit; the drag history still tells
        sys.exit(f"narwhal exited with {done.returncode} (2: input error, 3: diverged); see {d}")
    return time.monotonic() - t0


def run_openfoam(a, sets, s, d, iterations, write_interval=None):
    """One simpleFoam run on Narwhal's grid; its wall time (decomposition, the start
    stage and the solver's start-up, wall distance included; the mesh export excluded)."""
    shutil.rmtree(d, ignore_errors=True)
    subprocess.run([a.narwhal, "grid", a.case, "--out", str(d / "narwhal_grid"), "--openfoam", str(d)] + sets,
                   check=True, stdout=subprocess.DEVNULL)
    openfoam.write_case(d, s, iterations, write_interval)
    start = openfoam.StartStage(a.start_reynolds, a.start_iterations) if a.start_reynolds else None
    return openfoam.run(d, a.ranks, start=start)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case")
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--narwhal", default=str(ROOT / "build" / "solver" / "narwhal"))
    ap.add_argument("--out", default=str(ROOT / "reports" / "peer_body"))
    ap.add_argument("--iterations", type=int, default=3000, help="OpenFOAM iterations of the converging run")
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--repeat", type=int, default=3, help="timed runs of each code, stopped where it became steady")
    ap.add_argument("--steady", type=float, default=1e-3)
    ap.add_argument("--start-reynolds", type=float, default=0.0,
                    help="simpleFoam's first --start-iterations at this Reynolds number (0: none)")
    ap.add_argument("--start-iterations", type=int, default=100)
    a = ap.parse_args()
    if a.start_reynolds and not 0 < a.start_iterations < a.iterations:
        ap.error("--start-iterations must lie between 0 and --iterations")
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    overrides = dict(o.split("=", 1) for o in a.set)
    s = openfoam.case_settings(effective_input(SimpleNamespace(input=a.case, set=overrides)), a.case)
    sets = sum((["--set", x] for x in a.set), [])
    version = subprocess.run([a.narwhal, "--version"], capture_output=True, text=True).stdout.strip()
    identity = {"case": a.case, "set": a.set, "steady_tolerance": a.steady, "ranks": a.ranks, "repeat": a.repeat,
                "openfoam_iterations": a.iterations, "narwhal_version": version,
                "openfoam_start": {"reynolds": a.start_reynolds, "iterations": a.start_iterations}
                if a.start_reynolds else None}
    results = resumed(out / "peer_body.json", identity)
    save = lambda: (out / "peer_body.json").write_text(json.dumps(results, indent=1) + "\n")
    # 1. One run of each code well past its answer: where its drag became steady, and the
    #    answer itself.
    if "narwhal" not in results:
        run_narwhal(a, sets, out / "narwhal")
        n_it, _, n_cd = time_to_steady(narwhal_history(out / "narwhal"), a.steady)
        results["narwhal"] = {"iterations_to_steady": n_it, "cd": n_cd, "timed_s": []}
        save()
    if "openfoam" not in results:
        # The converging run may outlast a sitting: it writes its solution every
        # CHECKPOINT iterations, and a stopped one continues from there (its wall time is
        # not the measurement; the timed runs below are).
        if results.get("openfoam_started") and (out / "openfoam" / "log.simpleFoam").exists():
            openfoam.resume(out / "openfoam", a.ranks)
        else:
            results["openfoam_started"] = True
            save()
            run_openfoam(a, sets, s, out / "openfoam", a.iterations, write_interval=CHECKPOINT)
        f_it, _, f_cd = time_to_steady(foam_history(out / "openfoam", s), a.steady)
        if a.start_reynolds and f_it <= a.start_iterations:  # steady at the start stage's Re is not the answer
            sys.exit(f"simpleFoam's drag was steady from iteration {f_it}, inside its start stage: "
                     "run it longer (--iterations)")
        results["openfoam"] = {"iterations_to_steady": f_it, "cd": f_cd, "timed_s": []}
        save()
    print(json.dumps(results), flush=True)
    # 2. Time to that answer: each code run again from scratch and stopped there,
    #    alternately, `repeat` times (the machine is noisy: medians). Each finished run is
    #    saved, so that a benchmark longer than one sitting continues where it stopped.
    n_it, f_it = results["narwhal"]["iterations_to_steady"], results["openfoam"]["iterations_to_steady"]
    for rep in range(a.repeat):
        if len(results["narwhal"]["timed_s"]) <= rep:
            results["narwhal"]["timed_s"].append(run_narwhal(a, sets, out / f"narwhal_t{rep}", n_it))
            save()
        if len(results["openfoam"]["timed_s"]) <= rep:
            results["openfoam"]["timed_s"].append(run_openfoam(a, sets, s, out / f"openfoam_t{rep}", f_it))
            save()
        print(json.dumps({c: results[c]["timed_s"][rep] for c in ("narwhal", "openfoam")}), flush=True)
    for code in ("narwhal", "openfoam"):
        results[code]["median_s_to_steady"] = statistics.median(results[code]["timed_s"])
    results["speed_ratio"] = results["openfoam"]["median_s_to_steady"] / results["narwhal"]["median_s_to_steady"]
    save()
    print(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
