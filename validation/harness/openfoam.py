"""OpenFOAM's simpleFoam (k-omega SST or Launder-Sharma k-epsilon) as a peer run on exactly Narwhal's grid (exported
with `narwhal grid --openfoam`): one place that writes the OpenFOAM case from a Narwhal
case file, runs it, and turns its forces into Narwhal's run.json layout, so that a rung's
extractors read a peer run as they read a Narwhal run (harness runs with peer =
"openfoam"; benchmarks/peer/openfoam_body.py times the two codes).

Both codes solve the same non-dimensional problem: U = 1 along the case's free stream
(angle of attack and drift in the grid axes of solver/motion/grid_axes.hpp), L = 1,
nu = 1 / Re, the case's free-stream turbulence, rho = 1; coefficients on 1/2 U^2 A_ref
(and A_ref L_ref for moments) about the case's moment centre.

Wall conditions differ in omega: narwhal puts Menter's value on the wall face (60 nu /
(beta_1 dy1^2), dy1 the wall cell's height), simpleFoam's omegaWallFunction fixes the wall
cell's omega at 6 nu / (beta_1 y^2). Menter's value as a fixedValue face condition diverged
in simpleFoam within 90 iterations on the 426 k-cell spheroid. On that grid (wall cell
centres at y+ 0.5) simpleFoam's skin friction is about 4 % below narwhal's along the whole
attached windward side; on the TMR plate narwhal's Cf(0.97) moves 0.2 % between wall cells
at y+ 0.2 and 0.9, while the value from the cell-centre distance (4 times larger) lowers it
4 % at y+ 0.9 (tmr_flat_plate, sst_137_tall_wall_cells). So narwhal keeps its default and
spheroid_turbulent compares with narwhal's turbulence.omega_wall = "cell_centre", which
brings the friction drags within 0.7 % (solver/turbulence/DESIGN.md).
The free stream's turbulence is sustained as narwhal's when the case asks
(turbulence.sustain_freestream): constant sources in constant/fvOptions. A peer run may
start from a Narwhal run's solution on the same grid (seed_from_narwhal says why), or from
the uniform stream after a start stage at a lower Reynolds number (StartStage says why).

Schemes (second order, bounded where OpenFOAM's steady solver needs it): linearUpwind for
momentum, limitedLinear for k and omega (first-order upwind, as narwhal convects them,
NUMERICS §8.6, made the 426 k-cell spheroid diverge near iteration 110), cell-limited
gradients, limited non-orthogonal correction (the body grids' non-orthogonality reaches 60
degrees near the pole squares); SIMPLE with GAMG for the pressure, relaxed 0.3 (p) and 0.7
(U, k, omega). SIMPLEC (p unrelaxed, U 0.8) converged on the 53 k-cell spheroid grid but
diverged from the first iterations on the 426 k one (wall cells' aspect ratio near 8000).
OpenFOAM (Debian package `openfoam`) is installed by ci/nightly only, never by CI.
"""
import json
import math
import re
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .captive import BODY_AXES
from .errors import HarnessError

FOAM_BASHRC = "/usr/share/openfoam/etc/bashrc"  # Debian's OpenFOAM environment

HEADER = """FoamFile
{{
    version 2.0;
    format ascii;
    class {cls};
    object {obj};
}}
"""


def available():
    return Path(FOAM_BASHRC).exists()


def _write(path, cls, obj, body):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(HEADER.format(cls=cls, obj=obj) + body)


def foam(cmd, cwd, log, timeout=None):
    """An OpenFOAM utility inside its environment (Debian: source etc/bashrc first)."""
    from .runner import mpi_environment  # runner imports this module where it runs a peer
    script = f"source {FOAM_BASHRC} >/dev/null 2>&1; exec " + " ".join(cmd)
    with open(log, "w") as f:
        done = subprocess.run(["bash", "-c", script], cwd=cwd, stdout=f, stderr=subprocess.STDOUT, timeout=timeout,
                              env=mpi_environment())
    if done.returncode != 0:
        raise HarnessError(f"OpenFOAM's {cmd[0]} failed (exit {done.returncode}); see {log}")


# Narwhal's turbulence.model -> OpenFOAM's RASModel and the fields it solves (with
# their wall conditions; the free stream as Narwhal's: k from the intensity, the second
# variable from the eddy-viscosity ratio).
MODELS = {"sst": "kOmegaSST", "launder-sharma": "LaunderSharmaKE"}


def free_stream_direction(alpha_deg, beta_deg):
    """The free stream in grid axes: solver/motion/grid_axes.hpp's free_stream_in_grid_axes
    (the body's nose at -x of the grid, z down): (cos a cos b, -sin b, -sin a cos b)."""
    a, b = math.radians(alpha_deg), math.radians(beta_deg)
    return (math.cos(a) * math.cos(b), -math.sin(b), -math.sin(a) * math.cos(b))


def case_settings(c, where):
    """What the peer case needs from a Narwhal case (the TOML tree with its overrides
    applied: runner.effective_input); `where` names it in messages."""
    t = c.get("turbulence", {})
    if t.get("model") not in MODELS:
        raise HarnessError(f"{where}: the OpenFOAM peer run solves {' or '.join(MODELS)}; the case's "
                           f"turbulence.model is {t.get('model')!r}")
    flow, out = c["flow"], c.get("output", {})
    re_ = float(flow["reynolds"])
    tu, ratio = float(t.get("intensity", 0.001)), float(t.get("freestream_nut_ratio", 3.0))
    k = 1.5 * tu * tu
    nut = ratio / re_
    return {"model": t["model"], "nu": 1.0 / re_, "k": k, "omega": k / nut, "epsilon": 0.09 * k * k / nut,
            "sustain": bool(t.get("sustain_freestream", False)),
            "direction": free_stream_direction(float(flow.get("angle_of_attack", 0.0)), float(flow.get("drift_angle", 0.0))),
            "area": float(out.get("reference_area", 1.0)), "length": float(out.get("reference_length", 1.0)),
            "centre": [float(x) for x in out.get("moment_centre", [0.0, 0.0, 0.0])]}


def sustaining_sources(s):
    """Per unit volume, the Spalart-Rumsey terms that keep the free stream's turbulence
    from decaying (narwhal's turbulence.sustain_freestream): minus each equation's point
    source at the free-stream values in a uniform flow. SST: k gains beta* k omega, omega
    gains beta omega^2 with beta = beta_2 (F1 = 0 off the body; narwhal blends with the
    local F1, which differs in the wall cells only, where the term is negligible).
    Launder-Sharma (epsilon-tilde; D = 0 in a uniform flow): k gains epsilon, epsilon
    gains C2 f2 epsilon^2 / k, f2 at the free stream's turbulence Reynolds number."""
    k = s["k"]
    if s["model"] == "sst":
        w = s["omega"]
        return {"k": 0.09 * k * w, "omega": 0.0828 * w * w}
    e = s["epsilon"]
    rt = k * k / (s["nu"] * e)
    f2 = 1.0 - 0.3 * math.exp(-min(rt * rt, 50.0))
    return {"k": e, "epsilon": 1.92 * f2 * e * e / k}


def _write_sustaining_sources(d, s):
    """constant/fvOptions with the sustaining terms as constant explicit sources, or none."""
    path = d / "constant" / "fvOptions"
    if not s.get("sustain"):
        path.unlink(missing_ok=True)
        return
    rates = "\n".join(f"        {name} ({value!r} 0);" for name, value in sustaining_sources(s).items())
    _write(path, "dictionary", "fvOptions", f"""
sustainFreeStream
{{
    type scalarSemiImplicitSource;
    active yes;
    selectionMode all;
    volumeMode specific;
    injectionRateSuSp
    {{
{rates}
    }}
}}
""")


def write_case(d, s, iterations, write_interval=None):
    """The OpenFOAM case in d for `iterations` SIMPLE iterations; the solution is written at
    the end, or every `write_interval` iterations (the last write kept) for a run that may
    have to be continued (resume)."""
    nu, k, w, e = s["nu"], s["k"], s["omega"], s["epsilon"]
    u = "({} {} {})".format(*(repr(x) for x in s["direction"]))
    _write(d / "constant" / "transportProperties", "dictionary", "transportProperties",
           f"transportModel Newtonian;\nnu {nu!r};\n")
    _write(d / "constant" / "turbulenceProperties", "dictionary", "turbulenceProperties",
           f"simulationType RAS;\nRAS {{ RASModel {MODELS[s['model']]}; turbulence on; printCoeffs off; }}\n")
    fields = {
        "U": ("volVectorField", "[0 1 -1 0 0 0 0]", f"uniform {u}",
              "body { type noSlip; }", f"farfield {{ type freestreamVelocity; freestreamValue uniform {u}; }}"),
        "p": ("volScalarField", "[0 2 -2 0 0 0 0]", "uniform 0",
              "body { type zeroGradient; }", "farfield { type freestreamPressure; freestreamValue uniform 0; }"),
        "k": ("volScalarField", "[0 2 -2 0 0 0 0]", f"uniform {k!r}",
              "body { type fixedValue; value uniform 1e-14; }",
              f"farfield {{ type inletOutlet; inletValue uniform {k!r}; value uniform {k!r}; }}"),
        "omega": ("volScalarField", "[0 0 -1 0 0 0 0]", f"uniform {w!r}",
                  "body { type omegaWallFunction; value uniform 1; }",
                  f"farfield {{ type inletOutlet; inletValue uniform {w!r}; value uniform {w!r}; }}"),
        # Launder-Sharma solves epsilon-tilde, zero at the wall: 1e-14, as k, because
        # OpenFOAM traps the division by it in f_mu = f(k^2 / (nu eps)) on the wall faces
        "epsilon": ("volScalarField", "[0 2 -3 0 0 0 0]", f"uniform {e!r}",
                    "body { type fixedValue; value uniform 1e-14; }",
                    f"farfield {{ type inletOutlet; inletValue uniform {e!r}; value uniform {e!r}; }}"),
        "nut": ("volScalarField", "[0 2 -1 0 0 0 0]", "uniform 0",
                "body { type nutLowReWallFunction; value uniform 0; }", "farfield { type calculated; value uniform 0; }"),
    }
    del fields["epsilon" if s["model"] == "sst" else "omega"]
    for name, (cls, dim, internal, wall, farfield) in fields.items():
        _write(d / "0" / name, cls, name,
               f"dimensions {dim};\ninternalField {internal};\nboundaryField\n{{\n    {wall}\n    {farfield}\n}}\n")
    _write_sustaining_sources(d, s)
    c = s["centre"]
    _write(d / "system" / "controlDict", "dictionary", "controlDict", f"""
application simpleFoam;
startFrom startTime; startTime 0; stopAt endTime; endTime {iterations}; deltaT 1;
writeControl timeStep; writeInterval {write_interval or iterations}; purgeWrite 1; writeFormat binary;
runTimeModifiable false;
functions
{{
    forces
    {{
        type forces; libs ("libforces.so"); writeControl timeStep; writeInterval 1;
        patches (body); rho rhoInf; rhoInf 1; CofR ({c[0]!r} {c[1]!r} {c[2]!r});
    }}
    wallShearStress
    {{
        type wallShearStress; libs ("libfieldFunctionObjects.so"); patches (body);
        executeControl writeTime; writeControl writeTime; log false;
    }}
    wall
    {{
        type surfaces; libs ("libsampling.so"); writeControl onEnd; surfaceFormat raw;
        fields (p wallShearStress); interpolationScheme cell;
        surfaces ( body {{ type patch; patches (body); interpolate false; }} );
    }}
}}
""")
    _write(d / "system" / "fvSchemes", "dictionary", "fvSchemes", """
ddtSchemes { default steadyState; }
gradSchemes { default cellLimited Gauss linear 1; }
divSchemes
{
    default none;
    div(phi,U) bounded Gauss linearUpwind grad(U);
    div(phi,k) bounded Gauss limitedLinear 1;
    div(phi,omega) bounded Gauss limitedLinear 1;
    div(phi,epsilon) bounded Gauss limitedLinear 1;
    div((nuEff*dev2(T(grad(U))))) Gauss linear;
}
laplacianSchemes { default Gauss linear limited corrected 0.5; }
interpolationSchemes { default linear; }
snGradSchemes { default limited corrected 0.5; }
wallDist { method meshWave; }
""")
    _write(d / "system" / "fvSolution", "dictionary", "fvSolution", """
solvers
{
    p { solver GAMG; smoother GaussSeidel; tolerance 1e-10; relTol 0.05; }
    "(U|k|omega|epsilon)" { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-12; relTol 0.1; }
}
SIMPLE { nNonOrthogonalCorrectors 0; consistent no; }
relaxationFactors { equations { U 0.7; ".*" 0.7; } fields { p 0.3; } }
""")


# Each model's variables under narwhal's CGNS names (solver/turbulence/*.hpp, cgns_name)
# -> the OpenFOAM fields they seed; Launder-Sharma's epsilon is epsilon-tilde in both codes.
SEED_FIELDS = {"sst": {"TurbulentEnergyKinetic": "k", "TurbulentDissipationRate": "omega"},
               "launder-sharma": {"TurbulentEnergyKinetic": "k", "TurbulentDissipation": "epsilon"}}


def seed_from_narwhal(d, s, solution, grid):
    """Narwhal's solution (solution.cgns) as simpleFoam's initial fields in d/0. Why: on the
    426 k-cell spheroid simpleFoam's Launder-Sharma blew up from a uniform start within ten
    iterations (k 0.7 U^2 in a wall cell), and its SST run lives on a knife edge (two starts
    whose free-stream omega differs in the 16th digit: one ran 2000 iterations, the other
    diverged at iteration 70, at the windward nose). From Narwhal's converged fields neither
    blows up; the answer simpleFoam converges to is its own. `grid` is the grid.cgns that
    narwhal wrote with this OpenFOAM mesh: the solution must be on it, node for node. The
    export numbers cells block by block in the run's block order (CGNS Ordinal), i fastest
    (solver/io/openfoam_writer.cpp), which is the order of the flattened zones here."""
    from .solution import read_nodes, read_solution
    zones = sorted(read_solution(solution, extra=SEED_FIELDS[s["model"]]), key=lambda z: z.ordinal)
    nodes = read_nodes(grid)
    if not zones:
        raise HarnessError(f"{solution}: no zones with a flow solution")
    for z in zones:
        if z.name not in nodes or nodes[z.name].shape != z.x.shape or \
                np.abs(nodes[z.name] - z.x).max() > 1e-12 * max(np.abs(z.x).max(), 1.0):
            raise HarnessError(f"{solution}: block '{z.name}' is not the block of the peer's grid {grid}; "
                               "a peer run starts only from a Narwhal run on the same grid")
    flat = lambda key: np.concatenate([z.fields[key].ravel() for z in zones])
    values = {"U": np.stack([flat("u"), flat("v"), flat("w")], axis=1), "p": flat("p")}
    values.update({foam_name: flat(cgns) for cgns, foam_name in SEED_FIELDS[s["model"]].items()})
    cells = _cell_count(d)
    if cells != len(values["p"]):
        raise HarnessError(f"{solution}: {len(values['p'])} cells, the OpenFOAM mesh in {d} has {cells}")
    for name, v in values.items():
        path = d / "0" / name
        rows = "\n".join("({!r} {!r} {!r})".format(*map(float, r)) for r in v) if v.ndim == 2 else \
            "\n".join(repr(float(x)) for x in v)
        field = f"nonuniform List<{'vector' if v.ndim == 2 else 'scalar'}> {len(v)}\n(\n{rows}\n)"
        text, found = re.subn(r"internalField uniform [^;]+;", lambda m: f"internalField {field};", path.read_text(),
                              count=1)
        if not found:
            raise HarnessError(f"{path}: no uniform internalField to replace with Narwhal's")
        path.write_text(text)


@dataclass(frozen=True)
class StartStage:
    """simpleFoam's first `iterations` at Reynolds number `reynolds`, before the case's own:
    a Reynolds-number continuation. Why: from the uniform stream simpleFoam diverges within
    20 iterations on the SUBOFF grids (39 k to 1.3 M cells, wall cells at y+ 0.5 and at 5
    alike): in the second iteration the cells on the nose's stagnation line carry |U| of
    30-60 U (the uniform stream driven into the wall), with first-order upwind, lower
    relaxation or a velocity clamp alike, and with SIMPLEC on 1.06 M cells; at Re 1e3 the
    same grid runs (benchmarks/README.md)."""
    reynolds: float
    iterations: int


def _solve(d, ranks, log, timeout):
    if ranks > 1:
        foam(["mpirun", "-np", str(ranks), "--oversubscribe", "simpleFoam", "-parallel"], d, log, timeout)
    else:
        foam(["simpleFoam"], d, log, timeout)


def _edit(path, pattern, value):
    """One `key value;` entry of a dictionary that write_case wrote; its old value."""
    text = path.read_text()
    m = re.search(pattern, text, flags=re.M)
    if not m:
        raise HarnessError(f"{path}: no entry matching {pattern!r}")
    path.write_text(text[:m.start(1)] + value + text[m.end(1):])
    return m.group(1)


def run(d, ranks, timeout=None, start=None):
    """simpleFoam in d (its mesh in d/constant/polyMesh); the wall time of the solver alone,
    the start stage's (a StartStage, or None) included."""
    t0 = time.monotonic()
    if ranks > 1:
        # Slabs along x, equal in cell count (Debian's OpenFOAM has no scotch).
        _write(d / "system" / "decomposeParDict", "dictionary", "decomposeParDict",
               f"numberOfSubdomains {ranks};\nmethod simple;\n"
               f"simpleCoeffs {{ n ({ranks} 1 1); delta 0.001; }}\n")
        foam(["decomposePar", "-force"], d, d / "log.decomposePar", timeout)
    if start:
        # A parallel run reads constant/transportProperties from the case, not the processors.
        transport, control = d / "constant" / "transportProperties", d / "system" / "controlDict"
        nu = _edit(transport, r"^nu (\S+);", repr(1.0 / start.reynolds))
        end = _edit(control, r"endTime (\d+);", str(start.iterations))
        interval = _edit(control, r"writeInterval (\d+);", str(start.iterations))
        _solve(d, ranks, d / "log.start", timeout)
        _edit(transport, r"^nu (\S+);", nu)
        _edit(control, r"endTime (\d+);", end)
        _edit(control, r"writeInterval (\d+);", interval)
        _edit(control, r"startFrom (\w+);", "latestTime")
        timeout = None if timeout is None else max(timeout - (time.monotonic() - t0), 1.0)
    _solve(d, ranks, d / "log.simpleFoam", timeout)
    return time.monotonic() - t0


def resume(d, ranks, timeout=None):
    """Continue the case's stage of a run that was stopped (its sitting ended) from its last
    written iteration, in a further log (log.simpleFoam.2, .3 ...; history() reads them in
    order); the wall time of this leg alone. The iterations after that write are repeated."""
    t0 = time.monotonic()
    if not (d / "log.simpleFoam").exists():
        raise HarnessError(f"{d}: no log.simpleFoam: the case's stage never started, nothing to continue")
    _edit(d / "system" / "controlDict", r"startFrom (\w+);", "latestTime")
    _solve(d, ranks, d / f"log.simpleFoam.{len(_legs(d)) + 1}", timeout)
    return time.monotonic() - t0


def _legs(d):
    """The case stage's logs in the order they were run: log.simpleFoam, then resume's."""
    more = sorted(d.glob("log.simpleFoam.*"), key=lambda p: int(p.suffix[1:]))
    return [d / "log.simpleFoam"] + more if (d / "log.simpleFoam").exists() else []


def _in_run_order(base, name):
    """The forces function object's files: one folder per (re)start, named by its start time;
    a restart at a time that already has a folder writes name_<time>.dat beside the first."""
    return sorted(base.glob(f"*/{name}*.dat"), key=lambda f: (float(f.parent.name), f.stat().st_mtime))


def _numbers(line):
    return [float(x) for x in re.sub(r"[()]", " ", line).split()]


def history(d, s):
    """Per iteration: (iteration, wall seconds, coefficients in grid axes {cfx .. cmz},
    their pressure and viscous parts) from the forces function object."""
    wall = {}
    offset = 0.0  # the start stage's solver time: its ExecutionTime restarts in the case's stage
    for log in [d / "log.start"] + _legs(d):
        if not log.exists():
            continue
        it, last = None, 0.0
        for line in log.read_text().splitlines():
            m = re.match(r"^Time = (\d+)", line)
            if m:
                it = int(m.group(1))
            m = re.search(r"ExecutionTime = ([\d.eE+-]+) s", line)
            if m and it is not None:
                last = float(m.group(1))
                wall[it] = offset + last
        offset += last
    base = d / "postProcessing" / "forces"
    force_files, moment_files = _in_run_order(base, "force"), _in_run_order(base, "moment")
    if not force_files or not moment_files:
        raise HarnessError(f"{base}: no force.dat / moment.dat (did simpleFoam run?)")
    q = 0.5 * s["area"]  # rho = U = 1

    def by_iteration(files):  # a continued run repeats iterations: the later leg's values hold
        rows = {}
        for line in (line for f in files for line in f.read_text().splitlines()):
            if not line.startswith("#") and line.strip():
                v = _numbers(line)
                rows[int(v[0])] = v[1:]
        return rows
    forces, moments = by_iteration(force_files), by_iteration(moment_files)
    rows = []
    for i in sorted(forces):
        if i not in moments or i not in wall:
            continue
        f, m = forces[i], moments[i]  # total, pressure, viscous: 3 components each
        parts = {}
        for name, off in (("total", 0), ("pressure", 3), ("friction", 6)):
            parts[name] = {**{f"cf{a}": f[off + j] / q for j, a in enumerate("xyz")},
                           **{f"cm{a}": m[off + j] / (q * s["length"]) for j, a in enumerate("xyz")}}
        rows.append((i, wall[i], parts))
    if not rows:
        raise HarnessError(f"{d}: simpleFoam wrote no forces")
    return rows


def body_axes(c):
    """Grid-axes coefficients (cfx ... cmz) to the body axes, in run.json's names."""
    return {name: sign * c[column] for name, (column, sign) in BODY_AXES.items()}


def write_results(d, out, s, solver_seconds):
    """run.json, history.csv and surface_body.csv in Narwhal's layouts, so that the
    harness's extractors read the peer run as they read a Narwhal run."""
    rows = history(d, s)
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "history.csv", "w") as f:
        f.write(f"# OpenFOAM simpleFoam ({MODELS[s['model']]}) on Narwhal's grid; forces on the patch body, grid axes\n")
        f.write("iteration,wall_s,body_cfx,body_cfy,body_cfz,body_cmx,body_cmy,body_cmz\n")
        for i, w, p in rows:
            t = p["total"]
            f.write(f"{i},{w!r}," + ",".join(repr(t[k]) for k in ("cfx", "cfy", "cfz", "cmx", "cmy", "cmz")) + "\n")
    last = rows[-1][2]
    body = dict(last["total"])
    body["pressure"], body["friction"] = last["pressure"], last["friction"]
    body["body_axes"] = body_axes(last["total"])
    window = [r[2]["total"]["cfx"] for r in rows[-20:]]
    span = (max(window) - min(window)) / max(abs(window[-1]), 1e-300)
    cells = _cell_count(d)
    run_json = {"title": "OpenFOAM simpleFoam peer run", "status": "stopped",
                "message": f"simpleFoam ran its {rows[-1][0]} iterations", "iterations": rows[-1][0],
                "wall_seconds": solver_seconds, "cells": cells, "force_span": span,
                "forces": {"body": body},
                "provenance": {"version": _foam_version(d), "git_sha": "", "compiler": "Debian openfoam package",
                               "flags": "simpleFoam"}}
    (out / "run.json").write_text(json.dumps(run_json, indent=1) + "\n")
    _write_surface(d, out)
    return run_json


def _cell_count(d):
    """From the owner file's header note, which narwhal's writer fills as OpenFOAM's does."""
    owner = (d / "constant" / "polyMesh" / "owner").read_text(errors="replace")
    m = re.search(r"nCells:\s*(\d+)", owner)
    return int(m.group(1)) if m else None


def _foam_version(d):
    log = (d / "log.simpleFoam").read_text(errors="replace")
    m = re.search(r"Version:\s*(\S+)", log)
    return f"OpenFOAM {m.group(1)}" if m else "OpenFOAM"


def _raw(d, field):
    """The last raw sample of a field on the patch body (x y z and the values, per face)."""
    found = sorted((d / "postProcessing" / "wall").glob(f"*/{field}_body.raw")) or \
        sorted((d / "postProcessing" / "wall").glob(f"*/body/{field}.raw"))
    if not found:
        return None
    rows = [line.split() for line in found[-1].read_text().splitlines() if line.strip() and not line.startswith("#")]
    return [[float(v) for v in r] for r in rows]


def _write_surface(d, out):
    """The wall pressure and shear the surfaces function object wrote (raw: x y z p, and
    x y z tau per face) as surface_body.csv (x, y, z, cp, cf_x, cf_y, cf_z): cp = 2 p with
    rho = U = 1; cf = -2 tau, because OpenFOAM's wallShearStress is the stress on the fluid
    (its face normal into the fluid dotted with R_eff = -nu_eff dev(2 symm grad U)),
    and narwhal's cf the friction on the body."""
    p = _raw(d, "p")
    if p is None:
        return
    tau = _raw(d, "wallShearStress")
    if tau is not None and (len(tau) != len(p) or any(a[:3] != b[:3] for a, b in zip(p, tau))):
        raise HarnessError(f"{d}: the wall pressure and shear samples are not of the same faces")
    with open(out / "surface_body.csv", "w") as f:
        f.write("# OpenFOAM simpleFoam peer run: wall pressure and shear of the patch body, face centres; "
                "cp = 2 p, cf = -2 wallShearStress\n")
        f.write("x,y,z,cp" + (",cf_x,cf_y,cf_z" if tau else "") + "\n")
        for n, (x, y, z, pv) in enumerate(r[:4] for r in p):
            cf = "".join(f",{-2.0 * v!r}" for v in tau[n][3:6]) if tau else ""
            f.write(f"{x!r},{y!r},{z!r},{2.0 * pv!r}{cf}\n")
