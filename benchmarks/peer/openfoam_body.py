#!/usr/bin/python3
"""Peer run on a body grid: OpenFOAM's simpleFoam (k-omega SST) on exactly Narwhal's
grid (exported with `narwhal grid --openfoam`), beside Narwhal on the same case.

Both codes solve the same non-dimensional problem (U = 1, L = 1, nu = 1 / Re, the
case's free-stream turbulence), and both report the force coefficient on 1/2 U^2 A_ref.
A code's time to its answer is the wall time at the first iteration after which its
drag stays within `--steady` (0.1 %) of its own final value; each code runs until its
forces have long settled, and the final values are compared side by side.

OpenFOAM (Debian package `openfoam`) is installed by ci/nightly only, never by CI.
Schemes: linearUpwind for momentum, limited linear for k and omega, cell-limited
gradients, limited non-orthogonal correction (the grids' non-orthogonality reaches 60
degrees near the pole squares); SIMPLEC with GAMG for the pressure.

  benchmarks/peer/openfoam_body.py CASE.toml [--set key=value ...] [--narwhal build/solver/narwhal]
      [--out DIR] [--iterations N] [--ranks 2] [--repeat 3]
"""
import argparse
import json
import re
import shutil
import statistics
import subprocess
import sys
import time
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FOAM_BASHRC = "/usr/share/openfoam/etc/bashrc"  # Debian's OpenFOAM environment

HEADER = """FoamFile
{{
    version 2.0;
    format ascii;
    class {cls};
    object {obj};
}}
"""


def write(path, cls, obj, body):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(HEADER.format(cls=cls, obj=obj) + body)


def foam(cmd, cwd, log):
    """An OpenFOAM utility inside its environment (Debian: source etc/bashrc first)."""
    script = f"source {FOAM_BASHRC} >/dev/null 2>&1; exec " + " ".join(cmd)
    with open(log, "w") as f:
        subprocess.run(["bash", "-c", script], cwd=cwd, stdout=f, stderr=subprocess.STDOUT, check=True)


def case_settings(case_toml, overrides):
    with open(case_toml, "rb") as f:
        c = tomllib.load(f)
    for o in overrides:
        key, value = o.split("=", 1)
        node = c
        *path, last = key.split(".")
        for p in path:
            node = node.setdefault(p, {})
        node[last] = tomllib.loads(f"v = {value}")["v"]
    t = c.get("turbulence", {})
    if t.get("model") != "sst":
        sys.exit(f"{case_toml}: the peer run compares k-omega SST; the case's model is {t.get('model')!r}")
    re_ = float(c["flow"]["reynolds"])
    tu, ratio = float(t.get("intensity", 0.001)), float(t.get("freestream_nut_ratio", 3.0))
    k = 1.5 * tu * tu
    area = float(c.get("output", {}).get("reference_area", 1.0))
    centre = c.get("output", {}).get("moment_centre", [0.0, 0.0, 0.0])
    return {"nu": 1.0 / re_, "k": k, "omega": k / (ratio / re_), "area": area, "centre": centre}


def make_case(d, s, iterations):
    nu, k, w = s["nu"], s["k"], s["omega"]
    write(d / "constant" / "transportProperties", "dictionary", "transportProperties",
          f"transportModel Newtonian;\nnu {nu!r};\n")
    write(d / "constant" / "turbulenceProperties", "dictionary", "turbulenceProperties",
          "simulationType RAS;\nRAS { RASModel kOmegaSST; turbulence on; printCoeffs off; }\n")
    far = "farfield"
    fields = {
        "U": ("volVectorField", "[0 1 -1 0 0 0 0]", "uniform (1 0 0)",
              "body { type noSlip; }", f"{far} {{ type freestreamVelocity; freestreamValue uniform (1 0 0); }}"),
        "p": ("volScalarField", "[0 2 -2 0 0 0 0]", "uniform 0",
              "body { type zeroGradient; }", f"{far} {{ type freestreamPressure; freestreamValue uniform 0; }}"),
        "k": ("volScalarField", "[0 2 -2 0 0 0 0]", f"uniform {k!r}",
              "body { type fixedValue; value uniform 1e-14; }",
              f"{far} {{ type inletOutlet; inletValue uniform {k!r}; value uniform {k!r}; }}"),
        "omega": ("volScalarField", "[0 0 -1 0 0 0 0]", f"uniform {w!r}",
                  "body { type omegaWallFunction; value uniform 1; }",
                  f"{far} {{ type inletOutlet; inletValue uniform {w!r}; value uniform {w!r}; }}"),
        "nut": ("volScalarField", "[0 2 -1 0 0 0 0]", "uniform 0",
                "body { type nutLowReWallFunction; value uniform 0; }", f"{far} {{ type calculated; value uniform 0; }}"),
    }
    for name, (cls, dim, internal, wall, farfield) in fields.items():
        write(d / "0" / name, cls, name,
              f"dimensions {dim};\ninternalField {internal};\nboundaryField\n{{\n    {wall}\n    {farfield}\n}}\n")
    c = s["centre"]
    write(d / "system" / "controlDict", "dictionary", "controlDict", f"""
application simpleFoam;
startFrom startTime; startTime 0; stopAt endTime; endTime {iterations}; deltaT 1;
writeControl timeStep; writeInterval {iterations}; purgeWrite 1; writeFormat binary;
runTimeModifiable false;
functions
{{
    forces
    {{
        type forceCoeffs; libs ("libforces.so"); writeControl timeStep; writeInterval 1;
        patches (body); rho rhoInf; rhoInf 1; liftDir (0 0 -1); dragDir (1 0 0); pitchAxis (0 1 0);
        CofR ({c[0]} {c[1]} {c[2]}); magUInf 1; lRef 1; Aref {s['area']!r};
    }}
}}
""")
    write(d / "system" / "fvSchemes", "dictionary", "fvSchemes", """
ddtSchemes { default steadyState; }
gradSchemes { default cellLimited Gauss linear 1; }
divSchemes
{
    default none;
    div(phi,U) bounded Gauss linearUpwind grad(U);
    div(phi,k) bounded Gauss limitedLinear 1;
    div(phi,omega) bounded Gauss limitedLinear 1;
    div((nuEff*dev2(T(grad(U))))) Gauss linear;
}
laplacianSchemes { default Gauss linear limited corrected 0.5; }
interpolationSchemes { default linear; }
snGradSchemes { default limited corrected 0.5; }
wallDist { method meshWave; }
""")
    write(d / "system" / "fvSolution", "dictionary", "fvSolution", """
solvers
{
    p { solver GAMG; smoother GaussSeidel; tolerance 1e-10; relTol 0.05; }
    "(U|k|omega)" { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-12; relTol 0.1; }
}
SIMPLE { nNonOrthogonalCorrectors 0; consistent yes; }
relaxationFactors { equations { U 0.8; ".*" 0.6; } fields { p 1; } }
""")


def foam_history(d):
    """(iteration, wall seconds, Cd) of the OpenFOAM run."""
    times = {}
    it = None
    for line in (d / "log.simpleFoam").read_text().splitlines():
        m = re.match(r"^Time = (\d+)", line)
        if m:
            it = int(m.group(1))
        m = re.search(r"ExecutionTime = ([\d.eE+-]+) s", line)
        if m and it is not None:
            times[it] = float(m.group(1))
    coeffs = sorted((d / "postProcessing" / "forces").glob("*/coefficient.dat")) + \
        sorted((d / "postProcessing" / "forces").glob("*/forceCoeffs.dat"))
    if not coeffs:
        sys.exit(f"{d}: no forceCoeffs output")
    rows = []
    names = None
    for line in coeffs[0].read_text().splitlines():
        if line.startswith("#"):
            parts = line[1:].split()
            if parts and parts[0] == "Time":
                names = parts
            continue
        v = line.split()
        if names and len(v) == len(names):
            i = int(float(v[0]))
            if i in times:
                rows.append((i, times[i], float(v[names.index("Cd")])))
    return rows


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
    s = case_settings(a.case, a.set)
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
        make_case(fd, s, a.iterations)
        if a.ranks > 1:
            write(fd / "system" / "decomposeParDict", "dictionary", "decomposeParDict",
                  f"numberOfSubdomains {a.ranks};\nmethod scotch;\n")
            foam(["decomposePar", "-force"], fd, fd / "log.decomposePar")
            foam(["mpirun", "-np", str(a.ranks), "--oversubscribe", "simpleFoam", "-parallel"], fd, fd / "log.simpleFoam")
        else:
            foam(["simpleFoam"], fd, fd / "log.simpleFoam")
        it, wall, cd = time_to_steady(foam_history(fd), a.steady)
        results["openfoam"].append({"iterations_to_steady": it, "wall_s_to_steady": wall, "cd": cd})
        print(json.dumps({"narwhal": results["narwhal"][-1], "openfoam": results["openfoam"][-1]}), flush=True)
    for code in ("narwhal", "openfoam"):
        results[f"{code}_median_wall_s_to_steady"] = statistics.median(r["wall_s_to_steady"] for r in results[code])
    results["speed_ratio"] = results["openfoam_median_wall_s_to_steady"] / results["narwhal_median_wall_s_to_steady"]
    (out / "peer_body.json").write_text(json.dumps(results, indent=1) + "\n")
    print(json.dumps({k: v for k, v in results.items() if k not in ("narwhal", "openfoam")}, indent=1))


if __name__ == "__main__":
    main()
