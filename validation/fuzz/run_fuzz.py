#!/usr/bin/python3
"""Runs narwhal on every mutant of the fuzz corpus (see make_corpus.py) and judges it.

  validation/fuzz/run_fuzz.py --narwhal build-asan/solver/narwhal

A case or grid mutant is checked (`narwhal check`); when the check passes it also
runs two iterations. A --set mutant is checked. A restart mutant is continued from.
Each process must end within the time limit (else: hang), with exit status 0, 1, 2
or 3 (else, or on a signal: crash), without a sanitizer report, and below the memory
limit; an input error (exit 2) must print a message that names the file concerned
and where in it (a key, a byte offset, a dataset or attribute). Writes
fuzz_results.json in --work and ends with 'N passed, M failed'.
"""
import argparse
import concurrent.futures
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
CORPUS = HERE / "corpus"
BASE = HERE / "base"

SANITIZER = re.compile(r"ERROR: (AddressSanitizer|LeakSanitizer|UndefinedBehaviorSanitizer)|runtime error:")
# Where in the file: a key, a byte offset, a dataset, an attribute, an override, a block.
LOCATOR = re.compile(r"key '|byte|override '|dataset '|attribute '|turbulence model '|block '|line \d|:\d+:\d+: ")
ENV = dict(os.environ,
           ASAN_OPTIONS="exitcode=86:detect_leaks=1:abort_on_error=0:allocator_may_return_null=1",
           UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:exitcode=87")


def execute(cmd, timeout, cwd):
    """(exit status or None on timeout, stderr text, peak resident memory in MB)."""
    with tempfile.TemporaryFile() as err:
        p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err, cwd=cwd, env=ENV, start_new_session=True)
        deadline = time.monotonic() + timeout
        status, usage = None, None
        while time.monotonic() < deadline:
            pid, st, ru = os.wait4(p.pid, os.WNOHANG)
            if pid:
                status, usage = st, ru
                break
            time.sleep(0.01)
        if status is None:
            os.killpg(p.pid, signal.SIGKILL)
            _, _, usage = os.wait4(p.pid, 0)
            rc = None
        else:
            rc = os.waitstatus_to_exitcode(status)
        p.returncode = rc  # reaped here, not by Popen
        err.seek(0)
        return rc, err.read().decode(errors="replace"), usage.ru_maxrss / 1024.0


def judge(name, cmd, file_named, args):
    t0 = time.monotonic()
    rc, err, mb = execute(cmd, args.timeout, args.work)
    seconds = time.monotonic() - t0
    verdict = "ok"
    if rc is None:
        verdict = f"hang (over {args.timeout:g} s)"
    elif SANITIZER.search(err):
        verdict = "sanitizer report"
    elif rc not in (0, 1, 2, 3):
        verdict = f"crash (exit {rc})"
    elif mb > args.memory_mb:
        verdict = f"memory {mb:.0f} MB over {args.memory_mb} MB"
    elif rc == 2:
        if "narwhal: error" not in err:
            verdict = "exit 2 without an error message"
        elif file_named not in err:
            verdict = f"message does not name '{file_named}'"
        elif not LOCATOR.search(err):
            verdict = "message does not say where (key, byte, dataset ...)"
    return {"name": name, "command": " ".join(map(str, cmd)), "exit": rc, "peak_mb": round(mb, 1),
            "seconds": round(seconds, 2),
            "verdict": verdict, "stderr": err[-2000:]}


def case_item(path, args):
    check = judge(path.name, [args.narwhal, "check", path], path.name, args)
    if check["verdict"] != "ok" or check["exit"] != 0:
        return [check]
    out = Path(args.work) / "runs" / path.stem
    return [check, judge(path.name + " (run)", [args.narwhal, "run", path, "--out", out, "--max-iterations", "2"],
                         path.name, args)]


def grid_item(path, args):
    grid = f'grid.file="{path}"'
    case = BASE / "plot3d_box.toml"
    check = judge(path.name, [args.narwhal, "check", case, "--set", grid], path.name, args)
    if check["verdict"] != "ok" or check["exit"] != 0:
        return [check]
    out = Path(args.work) / "runs" / path.stem
    return [check, judge(path.name + " (run)", [args.narwhal, "run", case, "--set", grid, "--out", out,
                                                "--max-iterations", "2"], path.name, args)]


def set_item(line, n, args):
    base, assignment = line.split("\t", 1)
    case = BASE / base
    # An override is part of the case: the message names the case file (or the override).
    return [judge(f"set {n:03d}: {assignment}", [args.narwhal, "check", case, "--set", assignment], base, args)]


def restart_bases(args):
    """The restarts the recipes start from, written by the narwhal under test."""
    work = Path(args.work) / "restart_bases"
    plate = BASE / "plate.toml"
    made = {}
    def write(tag, extra):
        out = work / tag
        cmd = [args.narwhal, "run", plate, "--out", out, "--max-iterations", "5"] + extra
        r = subprocess.run(cmd, capture_output=True, text=True, env=ENV)
        if r.returncode not in (0, 1) or not (out / "restart.h5").exists():
            sys.exit(f"run_fuzz: cannot write the base restart ({' '.join(map(str, cmd))}):\n{r.stderr}")
        made[tag] = out / "restart.h5"
    write("plate", [])
    return made, write


def restart_items(args):
    made, write = restart_bases(args)
    good = made["plate"].read_bytes()
    mutants = []
    folder = Path(args.work) / "restart_mutants"
    folder.mkdir(parents=True, exist_ok=True)
    lines = [l for l in (CORPUS / "restarts.txt").read_text().splitlines() if l and not l.startswith("#")]
    for n, line in enumerate(lines):
        op, *rest = line.split(" ", 1)
        rest = rest[0] if rest else ""
        data = bytearray(good)
        if op == "flip":
            frac, xor = rest.split()
            i = min(int(float(frac) * len(data)), len(data) - 1)
            data[i] ^= int(xor)
        elif op == "flip_header":
            i, xor = (int(v) for v in rest.split())
            data[i] ^= xor
        elif op == "truncate":
            data = data[:int(float(rest) * len(data))]
        elif op == "append":
            data += b"\x01" * int(rest)
        elif op == "empty":
            data = bytearray()
        elif op == "model":
            write(f"model_{rest}", ["--set", f'turbulence.model="{rest}"'])
            data = bytearray(made[f"model_{rest}"].read_bytes())
        elif op == "grid":
            write(f"grid_{n}", ["--set", rest])
            data = bytearray(made[f"grid_{n}"].read_bytes())
        else:
            sys.exit(f"run_fuzz: unknown restart recipe '{line}'")
        path = folder / f"{n:03d}_{op}.h5"
        path.write_bytes(bytes(data))
        mutants.append(path)
    return mutants


def restart_item(path, args):
    out = Path(args.work) / "runs" / path.stem
    cmd = [args.narwhal, "run", BASE / "plate.toml", "--restart", path, "--out", out, "--max-iterations", "8"]
    r = judge(path.name, cmd, path.name, args)
    if r["verdict"] == "ok" and r["exit"] != 2:
        r["verdict"] = f"corrupt or foreign restart accepted (exit {r['exit']})"
    return [r]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--narwhal", required=True, help="the executable under test (an ASan+UBSan build in CI)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=20.0, help="seconds before a process counts as hung")
    ap.add_argument("--memory-mb", type=int, default=1024, help="peak resident memory allowed per process")
    ap.add_argument("--work", default=None, help="scratch folder (default: a new temporary one)")
    ap.add_argument("--only", choices=("cases", "grids", "sets", "restarts"), action="append")
    args = ap.parse_args()
    args.narwhal = str(Path(args.narwhal).resolve())
    args.work = args.work or tempfile.mkdtemp(prefix="narwhal_fuzz_")
    Path(args.work).mkdir(parents=True, exist_ok=True)
    only = set(args.only or ("cases", "grids", "sets", "restarts"))
    jobs = []
    if "cases" in only:
        jobs += [(case_item, p) for p in sorted((CORPUS / "cases").glob("*.toml"))]
    if "grids" in only:
        jobs += [(grid_item, p) for p in sorted((CORPUS / "grids").glob("*.xyz"))]
    if "sets" in only:
        lines = [l for l in (CORPUS / "sets.txt").read_text().splitlines() if l and not l.startswith("#")]
        jobs += [(lambda item, a, n=n: set_item(item, n, a), l) for n, l in enumerate(lines)]
    if "restarts" in only:
        jobs += [(restart_item, p) for p in restart_items(args)]
    started = time.monotonic()
    results = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for rs in pool.map(lambda j: j[0](j[1], args), jobs):
            results += rs
    bad = [r for r in results if r["verdict"] != "ok"]
    by_exit = {}
    for r in results:
        by_exit[r["exit"]] = by_exit.get(r["exit"], 0) + 1
    summary = {"mutants": len(jobs), "processes": len(results), "failed": len(bad), "exit_counts": by_exit,
               "peak_mb": max((r["peak_mb"] for r in results), default=0.0),
               "slowest_s": max((r["seconds"] for r in results), default=0.0),
               "wall_seconds": round(time.monotonic() - started, 1)}
    (Path(args.work) / "fuzz_results.json").write_text(json.dumps({"summary": summary, "results": results}, indent=1))
    for r in bad:
        print(f"FAIL {r['name']}: {r['verdict']}\n  {r['command']}\n  " + "\n  ".join(r["stderr"].splitlines()[-6:]))
    print(f"fuzz: {len(jobs)} mutants, {len(results)} processes, exits {dict(sorted(by_exit.items(), key=str))}, "
          f"peak memory {summary['peak_mb']:.0f} MB, slowest process {summary['slowest_s']:.1f} s, "
          f"{summary['wall_seconds']} s in all; details in "
          f"{Path(args.work) / 'fuzz_results.json'}")
    print(f"{len(results) - len(bad)} passed, {len(bad)} failed")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
