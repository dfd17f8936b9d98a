"""Runs one rung: its solver runs (with time-out), then its checks; writes results.json."""
import functools
import hashlib
import json
import os
import platform
import shutil
import subprocess
import time
import tomllib
import traceback
from pathlib import Path

from .compare import Curve, Family, compare
from .errors import HarnessError
from .motion import free_body_frame
from .captive import continuation_summary, ended_unsteady
from .extract import Context, extract
from .reference import ReferenceFile
from .references import resolve_reference
from .settings import rung_settings

EXIT_MEANING = {0: "converged", 1: "not converged (max_iterations or stalled: run.json tells)", 2: "input error", 3: "diverged"}


def git_sha(root):
    try:
        return subprocess.run(["git", "rev-parse", "--short=12", "HEAD"], cwd=root, capture_output=True, text=True,
                              check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def solver_source_fingerprint(root):
    """A digest of the committed files narwhal is built from (CMakeLists.txt and solver/ but its
    tests and notes), or None when any of them has uncommitted changes (or there is no git): a
    resumed report reuses a run only from the same solver sources."""
    def git(*args):
        return subprocess.run(["git", *args], cwd=root, capture_output=True, text=True, check=True).stdout

    built_from = lambda path: not path.startswith("solver/tests/") and not path.endswith(".md")  # noqa: E731
    try:
        dirty = [line[3:] for line in git("status", "--porcelain", "--", "solver", "CMakeLists.txt").splitlines()]
        blobs = [line.split(None, 3) for line in git("ls-tree", "-r", "HEAD", "--", "solver", "CMakeLists.txt").splitlines()]
    except (OSError, subprocess.CalledProcessError):
        return None
    if any(built_from(path) for path in dirty):
        return None
    h = hashlib.sha256()
    for _mode, _kind, blob, path in blobs:
        if built_from(path):
            h.update(f"{path} {blob}\n".encode())
    return h.hexdigest()


def case_folder_digest(input_path):
    """sha256 over the files of a run's input folder but the rung file (case.toml): the input
    and whatever it names beside it (grids, tables); then, for each base the input is laid
    over that lies in another folder, that folder's files likewise (a base names its own
    grids and tables from its folder)."""
    h = hashlib.sha256()
    folders = []
    for path in [Path(input_path)] + base_chain(input_path):
        folder = path.resolve().parent
        if folder in folders:
            continue
        if folders:  # an input without bases elsewhere keeps the digest it always had
            h.update(b"\0base folder\0")
        folders.append(folder)
        for f in sorted(folder.iterdir()):
            if f.is_file() and f.name != "case.toml":
                h.update(f.name.encode())
                h.update(f.read_bytes())
    return h.hexdigest()


def base_chain(path):
    """The files a case file is laid over (`base`, relative to the file naming it), nearest
    first; refused as case_input refuses them."""
    return _read_chain(path)[1]


def _lay_over(under, over):
    for k, v in over.items():
        if isinstance(v, dict) and isinstance(under.get(k), dict):
            _lay_over(under[k], v)
        else:
            under[k] = v


def _read_chain(path):
    """The layers of a case file and its bases (nearest first), with the bases' paths."""
    path = Path(path)
    with open(path, "rb") as f:
        data = tomllib.load(f)
    seen = []
    layers = [data]
    while "base" in layers[-1]:
        base_path = Path(os.path.normpath(path.parent / layers[-1].pop("base")))
        if base_path in seen or len(seen) == 4:
            raise HarnessError(f"{path}: key 'base': the chain of bases through '{base_path}' loops or is deeper than 4")
        if not base_path.is_file():  # a device would be read without end
            raise HarnessError(f"{path}: key 'base': cannot open '{base_path}': expected a regular file")
        try:
            with open(base_path, "rb") as f:
                layers.append(tomllib.load(f))
        except OSError as e:
            raise HarnessError(f"{path}: key 'base': cannot open '{base_path}': {e}")
        seen.append(base_path)
        path = base_path
    return layers, seen


def case_input(path):
    """A case file as narwhal reads it: laid over its `base` (config/reader.hpp), which may
    have a base of its own (relative to its directory), four deep at most."""
    layers, _ = _read_chain(path)
    merged = layers.pop()
    while layers:
        _lay_over(merged, layers.pop())
    return merged


def effective_input(run):
    data = case_input(run.input)
    for key, literal in run.set.items():
        node = data
        parts = key.split(".")
        for p in parts[:-1]:
            node = node.setdefault(p, {})
        node[parts[-1]] = tomllib.loads("v = " + literal)["v"]
    return data


def _ordered(runs):
    """Runs after those they restart from; runs flown by a model after every other run (the
    model is assembled from their results)."""
    done, out = set(), []
    pending = [r for r in runs if not r.model] + [r for r in runs if r.model]
    while pending:
        for r in pending:
            if not r.restart_from or r.restart_from in done:
                out.append(r)
                done.add(r.id)
                pending.remove(r)
                break
        else:
            raise HarnessError("restart_from references form a cycle or name a run outside the tier")
    return out


def mpi_launcher(ranks):
    """The command prefix that starts `ranks` MPI processes (nothing for one rank).
    Oversubscribed: rungs compare 1, 2 and 3 ranks on a 2-core machine."""
    if ranks <= 1:
        return []
    exe = shutil.which("mpirun") or shutil.which("mpiexec")
    if not exe:
        raise HarnessError(f"{ranks} ranks asked for, but neither mpirun nor mpiexec is on PATH (apt: openmpi-bin)")
    return [exe, "-n", str(ranks), "--oversubscribe"]


@functools.lru_cache(maxsize=None)
def built_with_mpi(narwhal):
    """Whether this narwhal executable was built with NARWHAL_MPI (its --version says)."""
    try:
        out = subprocess.run([str(narwhal), "--version"], capture_output=True, text=True, timeout=30).stdout
    except (OSError, subprocess.SubprocessError):
        return False
    return out.rstrip().endswith(", MPI)")


def mpi_environment():
    env = dict(os.environ)
    if hasattr(os, "geteuid") and os.geteuid() == 0:  # containers and CI run as root
        env.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
        env.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    return env


def ranks_needed(rung, tier, ranks=1):
    """The most MPI ranks any of the rung's runs in `tier` uses (`ranks` for those that set none)."""
    return max([r.ranks or ranks for r in rung.runs if tier in r.tiers], default=1)


def run_rung(rung, tier, narwhal, out_dir, root, ranks=1, resume=False, simulator=None):
    """Runs the rung's runs of `tier`, then its checks. With `resume`, a Narwhal run whose folder
    holds the record of a finished run of the same command, case folder and solver sources
    (RUN_RECORD, written after each run) is not run again, and one that was interrupted goes on
    from the restart it wrote (RUN_STARTED): a nightly report can be built up over several
    sittings, however long its runs. Runs flown by a model use `simulator` (default: narwhal)."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    started = time.monotonic()
    result = {"rung": rung.name, "title": rung.title, "tier": tier, "status": "passed", "checks": [], "runs": [],
              "provenance": {"git_sha": git_sha(root), "machine": platform.node(), "platform": platform.platform(),
                             "python": platform.python_version()}}
    runs = _ordered([r for r in rung.runs if tier in r.tiers])
    most_ranks = ranks_needed(rung, tier, ranks)
    if most_ranks > 1 and not built_with_mpi(str(narwhal)):
        # Not a failure of the rung: this build cannot run it at all.
        result.update(status="skipped", message=f"needs {most_ranks} MPI ranks, but {narwhal} was built without MPI "
                                                "(configure with -DNARWHAL_MPI=ON)")
        return _finish(result, out_dir, started)
    run_dirs, inputs = {}, {}
    for r in runs:
        if r.when_unsteady:
            needed, info = _continuation_needed(r, out_dir)
            if not needed:
                result["runs"].append(info)
                if info["status"] == "input error":
                    result["status"] = "crashed"
                    break
                continue
        rd = out_dir / "runs" / r.id
        rd.mkdir(parents=True, exist_ok=True)
        remaining = rung.timeout_s - (time.monotonic() - started)
        if r.model:
            model = next(m for m in rung.models if m.id == r.model)
            info = _run_simulation(r, rd, model, Context(rung, run_dirs, inputs, root / "reference_data"),
                                   simulator or narwhal, remaining)
        elif r.code == "narwhal":
            key = _run_key(r, rd, r.ranks or ranks, narwhal, out_dir, root)
            info = (_recorded_run(rd, key) if resume else None) or \
                _run_narwhal(r, rd, r.ranks or ranks, narwhal, out_dir, remaining, key,
                             continue_run=resume and _interrupted_run(rd, key))
        else:
            info = _run_peer(r, rd, r.ranks or ranks, narwhal, out_dir, remaining)
        if "compiler" in info:
            result["provenance"].update({k: info.pop(k) for k in ("compiler", "flags", "version")})
        result["runs"].append(info)
        if info["status"] == "timeout":
            result["status"] = "timeout"
        elif info["status"] in ("input error", "diverged") or info["status"].startswith("crashed"):
            result["status"] = "crashed"
        if result["status"] in ("crashed", "timeout"):
            break
        run_dirs[r.id] = rd
        inputs[r.id] = effective_input(r)

    ctx = Context(rung, run_dirs, inputs, root / "reference_data")
    result["settings"] = rung_settings(ctx)
    try:
        result["unsteady_points"] = continuation_summary(ctx)
    except Exception as e:  # a harness bug must not cost the rung's checks: the page shows it instead
        result["unsteady_points"] = [{"sweep": "?", "force_span": 0.0, "discard": 0.0, "set": {},
                                      "points": [{"point": "?", "error": f"internal error: {e}"}]}]
    if result["status"] == "passed":
        for c in rung.checks:
            if tier not in c.tiers:
                continue
            entry = {"name": c.name, "comparator": c.comparator, "tolerance": c.tolerance, "rationale": c.rationale,
                     "options": c.options, "reference_source": ""}
            try:
                computed = extract(ctx, c.extract)
                ref_run = c.extract.get("run") or next((r.id for r in runs if r.family == c.extract.get("family")), None)
                reference, desc = resolve_reference(ctx, c.reference, root / "reference_data", ref_run)
                entry["reference_source"] = desc
                if reference is None and c.comparator not in ("restart_equal", "gci", "family_spread", "max", "min"):
                    raise HarnessError(f"check '{c.name}' has no reference")
                entry.update(compare(c.comparator, computed, reference, c.tolerance, c.options))
            except HarnessError as e:
                entry.update({"computed": None, "reference": None, "delta": None, "pass": False, "error": str(e),
                              "plot": None})
            except Exception as e:  # a harness bug must show as a failed check, with its trace
                entry.update({"computed": None, "reference": None, "delta": None, "pass": False, "plot": None,
                              "error": f"internal error: {e}\n{traceback.format_exc()}"})
            result["checks"].append(entry)
        result["reported"] = [_reported(ctx, q) for q in rung.reported if tier in q.tiers]
        result["pictures"] = [_picture(p, root / "reference_data", inputs.get(p.run, {}))
                              for p in rung.pictures if tier in p.tiers]
        if not result["checks"]:
            result["status"] = "failed"
            result["message"] = f"no check of rung '{rung.name}' belongs to tier '{tier}'"
        elif not all(ch["pass"] for ch in result["checks"]):
            result["status"] = "failed"
    return _finish(result, out_dir, started)


def _continuation_needed(r, out_dir):
    """Whether a sweep point's continuation in physical time (Run.when_unsteady) is to be made:
    (False, its entry of result["runs"]) when the point's steady run settled."""
    rj = out_dir / "runs" / r.restart_from / "run.json"
    try:
        data = json.loads(rj.read_text())
        if ended_unsteady(data, r.when_unsteady, r.restart_from):
            return True, None
    except (OSError, json.JSONDecodeError) as e:
        return False, {"id": r.id, "code": "narwhal", "status": "input error",
                       "message": f"{rj} cannot be read ({e}): whether the point ended steady cannot be told"}
    except HarnessError as e:
        return False, {"id": r.id, "code": "narwhal", "status": "input error", "message": str(e)}
    return False, {"id": r.id, "code": "narwhal", "status": "not needed",
                   "message": f"{r.restart_from} ended steady: force span {data['force_span']:.1e} "
                              f"<= {r.when_unsteady:g}"}


def _overrides(r):
    """The run's `set` table as narwhal's --set arguments (for `run` and `grid` alike)."""
    return [a for k, v in r.set.items() for a in ("--set", f"{k}={v}")]


def _narwhal_command(r, rd, n, narwhal, out_dir):
    cmd = mpi_launcher(n) + [str(narwhal), "run", str(r.input), "--out", str(rd)]
    cmd += _overrides(r)
    if r.max_iterations:
        cmd += ["--max-iterations", str(r.max_iterations)]
    if r.restart_from:
        cmd += ["--restart", str(out_dir / "runs" / r.restart_from / "restart.h5")]
    return cmd


RUN_RECORD = "harness_run.json"
# Written when a run starts: a resumed report continues an interrupted run of the same key
# from the restart.h5 it left (narwhal continues its own folder's history exactly).
RUN_STARTED = "harness_run_started.json"
REUSABLE = (0, 1)  # converged, or ended at max_iterations / stalled: results the checks judge


def _run_key(r, rd, n, narwhal, out_dir, root):
    """What a run's result depends on, or None when that cannot be pinned down (uncommitted
    solver sources, no MPI launcher): such a run is never reused."""
    sources = solver_source_fingerprint(root)
    try:
        cmd = _narwhal_command(r, rd, n, narwhal, out_dir)
        inputs = case_folder_digest(r.input)
    except HarnessError:  # the run itself says what is wrong
        return None
    if sources is None:
        return None
    return {"command": [_relative_to(root, a) for a in cmd], "case_folder_sha256": inputs, "solver_sources": sources}


def _relative_to(root, arg):
    """A command argument naming a path inside the checkout, relative to it: a run archived from
    one checkout (harness/archive.py) keeps its key in another."""
    root = Path(root).resolve()
    p = Path(arg)
    if p.is_absolute():
        try:
            return "<checkout>/" + p.resolve().relative_to(root).as_posix()
        except ValueError:
            pass
    return arg


def _recorded_run(rd, key):
    """The result["runs"] entry of a finished run recorded in `rd` under the same key, else None."""
    path = rd / RUN_RECORD
    if key is None or not path.exists() or not (rd / "run.json").exists():
        return None
    try:
        record = json.loads(path.read_text())
    except (OSError, json.JSONDecodeError):
        return None
    if record.get("key") != key or record.get("info", {}).get("exit_code") not in REUSABLE:
        return None
    return dict(record["info"], reused=True)


def _interrupted_run(rd, key):
    """Whether `rd` holds a run of the same key that started and did not finish, with the
    restart.h5 it wrote on the way."""
    path = rd / RUN_STARTED
    if key is None or not path.exists() or not (rd / "restart.h5").exists():
        return False
    try:
        return json.loads(path.read_text()).get("key") == key
    except (OSError, json.JSONDecodeError):
        return False


def _run_narwhal(r, rd, n, narwhal, out_dir, remaining, key=None, continue_run=False):
    """One Narwhal run (under mpirun for n > 1): its entry of result["runs"]; with a key, the
    record that lets a resumed report reuse it. With continue_run, it goes on from the
    restart.h5 an interrupted run of the same key left in `rd`."""
    (rd / RUN_RECORD).unlink(missing_ok=True)
    try:
        cmd = _narwhal_command(r, rd, n, narwhal, out_dir)
    except HarnessError as e:
        return {"id": r.id, "status": "crashed (no MPI launcher)", "message": str(e), "ranks": n}
    if continue_run:
        if "--restart" in cmd:  # its own restart is later than the run it started from
            i = cmd.index("--restart")
            del cmd[i:i + 2]
        cmd += ["--restart", str(rd / "restart.h5")]
    elif key is not None:
        (rd / RUN_STARTED).write_text(json.dumps({"key": key}, indent=1))
    info = {"id": r.id, "code": "narwhal", "command": " ".join(cmd), "log": f"runs/{r.id}/narwhal.log", "ranks": n}
    if continue_run:
        info["continued"] = True
    try:
        with open(rd / "narwhal.log", "a" if continue_run else "w") as log:
            proc = subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT, timeout=max(remaining, 1.0),
                                  env=mpi_environment())
        info["exit_code"] = proc.returncode
        info["status"] = EXIT_MEANING.get(proc.returncode, f"crashed (exit {proc.returncode})")
    except subprocess.TimeoutExpired:
        info["status"] = "timeout"
    rj = rd / "run.json"
    if rj.exists():
        with open(rj) as f:
            data = json.load(f)
        for k in ("iterations", "wall_seconds", "cells", "residual_drop", "status", "message"):
            info[k] = data.get(k)
        # Divergences the run went back from (solver.retreats): the report says so beside its status.
        info["retreats"] = len(data.get("retreats") or [])
        info.update({k: data["provenance"][k] for k in ("compiler", "flags", "version")})
    if key is not None and info.get("exit_code") in REUSABLE:
        (rd / RUN_RECORD).write_text(json.dumps({"key": key, "info": info}, indent=1))
        (rd / RUN_STARTED).unlink(missing_ok=True)
    return info


def model_file_text(model, ctx):
    """The model file (solver/app/simulate.hpp) with each value the result of its extractor
    on the rung's runs, and the extractor beside it."""
    lines = [f"# Manoeuvring model '{model.id}', assembled by the harness from the runs of rung '{ctx.rung.name}'."]
    for table, specs in (("coefficients", model.coefficients), ("propulsion", model.propulsion)):
        if not specs:
            continue
        lines.append(f"[{table}]")
        for name, spec in specs.items():
            try:
                value = float(extract(ctx, spec))
            except (TypeError, ValueError):
                raise HarnessError(f"model '{model.id}': {table}.{name}: its extractor gives no number")
            except HarnessError as e:
                raise HarnessError(f"model '{model.id}': {table}.{name}: {e}")
            lines.append(f"{name} = {value!r}   # {json.dumps(spec)}")
    return "\n".join(lines) + "\n"


def _run_simulation(r, rd, model, ctx, narwhal, remaining):
    """`narwhal simulate` on the run's case with the model assembled from the runs before it."""
    info = {"id": r.id, "code": "narwhal simulate", "log": f"runs/{r.id}/narwhal.log", "ranks": 1}
    try:
        (rd / "model.toml").write_text(model_file_text(model, ctx))
    except HarnessError as e:
        return dict(info, status="input error", message=str(e))
    cmd = [str(narwhal), "simulate", str(r.input), "--model", str(rd / "model.toml"), "--out", str(rd)] + _overrides(r)
    info["command"] = " ".join(cmd)
    try:
        with open(rd / "narwhal.log", "w") as log:
            proc = subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT, timeout=max(remaining, 1.0))
        info["exit_code"] = proc.returncode
        info["status"] = "completed" if proc.returncode == 0 else EXIT_MEANING.get(proc.returncode,
                                                                                   f"crashed (exit {proc.returncode})")
    except subprocess.TimeoutExpired:
        info["status"] = "timeout"
    return info


def _run_peer(r, rd, n, narwhal, out_dir, remaining):
    """A peer code's run on Narwhal's grid of the run's case (harness/openfoam.py): its
    outputs land in rd in Narwhal's layouts (run.json, history.csv, surface_body.csv)."""
    from . import openfoam
    info = {"id": r.id, "code": r.code, "log": f"runs/{r.id}/openfoam/log.simpleFoam", "ranks": n}
    if not openfoam.available():
        info.update(status="crashed (no OpenFOAM)",
                    message=f"{openfoam.FOAM_BASHRC} is missing: install Debian's openfoam (ci/nightly does)")
        return info
    case_dir = rd / "openfoam"
    shutil.rmtree(case_dir, ignore_errors=True)
    grid_cmd = [str(narwhal), "grid", str(r.input), "--out", str(rd / "grid"), "--openfoam", str(case_dir)]
    grid_cmd += _overrides(r)
    start = f", from run {r.restart_from}'s solution" if r.restart_from else ""
    info["command"] = " ".join(grid_cmd) + f" && simpleFoam ({r.max_iterations} iterations, {n} ranks{start})"
    started = time.monotonic()
    try:
        with open(rd / "grid.log", "w") as log:
            done = subprocess.run(grid_cmd, stdout=log, stderr=subprocess.STDOUT, timeout=max(remaining, 1.0))
        if done.returncode != 0:
            info.update(status="input error", message=f"narwhal grid exited with {done.returncode}; see runs/{r.id}/grid.log")
            return info
        settings = openfoam.case_settings(effective_input(r), r.input)
        openfoam.write_case(case_dir, settings, r.max_iterations)
        if r.restart_from:
            openfoam.seed_from_narwhal(case_dir, settings, out_dir / "runs" / r.restart_from / "solution.cgns",
                                       rd / "grid" / "grid.cgns")
        seconds = openfoam.run(case_dir, n, timeout=max(remaining - (time.monotonic() - started), 1.0))
        data = openfoam.write_results(case_dir, rd, settings, seconds)
    except subprocess.TimeoutExpired:
        info["status"] = "timeout"
        return info
    except HarnessError as e:
        info.update(status="crashed (peer run)", message=str(e))
        return info
    info.update(status="stopped at its iteration count", iterations=data["iterations"],
                wall_seconds=data["wall_seconds"], cells=data["cells"], message=data["message"],
                peer_version=data["provenance"]["version"])
    return info


def _reported(ctx, q):
    """A reported quantity's value (a number, or a curve the report draws: a sweep's
    coefficients), or the error that kept it from being extracted (shown in the report;
    it fails nothing, having no tolerance)."""
    entry = {"name": q.name, "unit": q.unit, "value": None}
    try:
        v = extract(ctx, q.extract)
        if isinstance(v, Family):
            raise HarnessError("a reported quantity must be a number or a curve, not a grid family")
        if isinstance(v, Curve):
            entry["curve"] = {"x": v.x.tolist(), "y": v.y.tolist(), "label": v.label}
            if v.yerr is not None:
                entry["curve"]["yerr"] = v.yerr.tolist()
            return entry
        entry["value"] = float(v)
    except HarnessError as e:
        entry["error"] = str(e)
    return entry


def _picture(p, reference_root, run_input):
    """What the report needs to draw a picture: the run's output files are read there;
    reference points (or, without x, reference levels) and a free body's gravity are
    read here, where reference_data/ and the run's input are at hand."""
    entry = {"kind": p.kind, "run": p.run, "title": p.title, "column": p.column, "group": p.group,
             "beside": p.beside, "stations": p.stations, "then": p.then}
    gravity = run_input.get("motion", {}).get("gravity")
    if gravity is not None:
        entry["gravity"] = [float(g) for g in gravity]
    if p.kind in ("side_view", "plan_view") or p.column in ("motion:rise", "motion:travel"):
        try:
            origin, stream, down = free_body_frame(run_input, f"picture of run '{p.run}'")
            entry["frame"] = {"origin": origin.tolist(), "stream": stream.tolist(), "down": down.tolist()}
        except HarnessError as e:
            entry["error"] = str(e)
    if p.reference:
        try:
            ref = ReferenceFile(reference_root, p.reference["file"])
            rows = ref.rows_where(p.reference["where"]) if "where" in p.reference else None
            entry["reference"] = {"x": ref.column(p.reference["x"], rows).tolist() if "x" in p.reference else None,
                                  "y": ref.column(p.reference["y"], rows).tolist(),
                                  "label": p.reference.get("label", p.reference["file"]),
                                  "source": ref.citation()}
        except (HarnessError, KeyError) as e:
            entry["error"] = f"reference points: {e}"
    return entry


def _finish(result, out_dir, started):
    result["wall_seconds"] = time.monotonic() - started
    result["cells"] = sum(r.get("cells") or 0 for r in result["runs"])
    result["iterations"] = sum(r.get("iterations") or 0 for r in result["runs"])
    result["provenance"].update(cells=result["cells"], iterations=result["iterations"],
                                wall_seconds=result["wall_seconds"])
    # Written whole or not at all: a half-written results.json would poison the report.
    tmp = out_dir / "results.json.tmp"
    with open(tmp, "w") as f:
        json.dump(result, f, indent=1)
    tmp.replace(out_dir / "results.json")
    return result
