#!/usr/bin/python3
"""Peer benchmark: the laminar flat plate (Re_L = 1e5) by OpenFOAM's simpleFoam and by
Narwhal, on the same grid, in the same run. Reports each code's Cf error against
Blasius over 0.1 < x < 0.9 and its wall time; writes peer.json (read by the report).

OpenFOAM (Debian package `openfoam`) is installed by ci/nightly only, never by CI.
The OpenFOAM case is generated here from the Narwhal case's grid parameters: two
blocks (run-up, plate) with the same cell counts and geometric gradings, second-order
schemes (linearUpwind for convection, linear for diffusion), SIMPLEC, run until every
initial residual is below 1e-6.

  benchmarks/peer/openfoam_flat_plate.py [--narwhal build/solver/narwhal] [--out DIR]
"""
import argparse
import json
import math
import re
import shutil
import subprocess
import sys
import time
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CASE = ROOT / "validation" / "cases" / "flat_plate_laminar" / "flat_plate.toml"
BLASIUS = ROOT / "reference_data" / "flat_plate" / "blasius_laminar_flat_plate.csv"

HEADER = """FoamFile
{{
    version 2.0;
    format ascii;
    class {cls};
    object {obj};
}}
"""


def growth_ratio(length, n, ds):
    """r with ds (r^n - 1)/(r - 1) = length (the same law as Narwhal's geometric_nodes)."""
    lo, hi = 1.0 + 1e-12, 2.0
    total = lambda r: ds * (r ** n - 1.0) / (r - 1.0)
    while total(hi) < length:
        hi *= 2.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if total(mid) < length else (lo, mid)
    return 0.5 * (lo + hi)


def write(path, cls, obj, body):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(HEADER.format(cls=cls, obj=obj) + body)


def make_case(d, g, nu):
    ru, L, H, W = g["runup"], g["length"], g["height"], g.get("width", 0.1)
    nr, npl, nn = g["cells_runup"], g["cells_plate"], g["cells_normal"]
    dle, dyw = g["dx_leading_edge"], g["dy_wall"]
    # simpleGrading = last cell / first cell along the block direction.
    r_run = growth_ratio(ru, nr, dle)      # grows away from the leading edge (towards -x)
    r_pl = growth_ratio(L, npl, dle)
    r_y = growth_ratio(H, nn, dyw)
    g_run, g_pl, g_y = 1.0 / r_run ** (nr - 1), r_pl ** (npl - 1), r_y ** (nn - 1)
    write(d / "system" / "blockMeshDict", "dictionary", "blockMeshDict", f"""
convertToMeters 1;
vertices
(
    ({-ru} 0 0) (0 0 0) ({L} 0 0) ({L} {H} 0) (0 {H} 0) ({-ru} {H} 0)
    ({-ru} 0 {W}) (0 0 {W}) ({L} 0 {W}) ({L} {H} {W}) (0 {H} {W}) ({-ru} {H} {W})
);
blocks
(
    hex (0 1 4 5 6 7 10 11) ({nr} {nn} 1) simpleGrading ({g_run:.12g} {g_y:.12g} 1)
    hex (1 2 3 4 7 8 9 10) ({npl} {nn} 1) simpleGrading ({g_pl:.12g} {g_y:.12g} 1)
);
boundary
(
    inlet {{ type patch; faces ((0 6 11 5)); }}
    outlet {{ type patch; faces ((2 3 9 8)); }}
    top {{ type patch; faces ((5 11 10 4) (4 10 9 3)); }}
    runup {{ type symmetryPlane; faces ((0 1 7 6)); }}
    plate {{ type wall; faces ((1 2 8 7)); }}
    sides {{ type empty; faces ((0 5 4 1) (1 4 3 2) (6 7 10 11) (7 8 9 10)); }}
);
""")
    write(d / "constant" / "transportProperties", "dictionary", "transportProperties",
          f"\ntransportModel Newtonian;\nnu {nu:.12g};\n")
    write(d / "constant" / "turbulenceProperties", "dictionary", "turbulenceProperties", "\nsimulationType laminar;\n")
    write(d / "0" / "U", "volVectorField", "U", """
dimensions [0 1 -1 0 0 0 0];
internalField uniform (1 0 0);
boundaryField
{
    inlet { type fixedValue; value uniform (1 0 0); }
    outlet { type zeroGradient; }
    top { type zeroGradient; }
    runup { type symmetryPlane; }
    plate { type noSlip; }
    sides { type empty; }
}
""")
    write(d / "0" / "p", "volScalarField", "p", """
dimensions [0 2 -2 0 0 0 0];
internalField uniform 0;
boundaryField
{
    inlet { type zeroGradient; }
    outlet { type fixedValue; value uniform 0; }
    top { type fixedValue; value uniform 0; }
    runup { type symmetryPlane; }
    plate { type zeroGradient; }
    sides { type empty; }
}
""")
    write(d / "system" / "controlDict", "dictionary", "controlDict", """
application simpleFoam;
startFrom latestTime;
stopAt endTime;
endTime 20000;
deltaT 1;
writeControl timeStep;
writeInterval 20000;
writeFormat ascii;
writePrecision 12;
runTimeModifiable false;
""")
    write(d / "system" / "fvSchemes", "dictionary", "fvSchemes", """
ddtSchemes { default steadyState; }
gradSchemes { default Gauss linear; }
divSchemes { default none; div(phi,U) bounded Gauss linearUpwind grad(U); div((nuEff*dev2(T(grad(U))))) Gauss linear; }
laplacianSchemes { default Gauss linear corrected; }
interpolationSchemes { default linear; }
snGradSchemes { default corrected; }
wallDist { method meshWave; }
""")
    write(d / "system" / "fvSolution", "dictionary", "fvSolution", """
solvers
{
    p { solver GAMG; smoother GaussSeidel; tolerance 1e-9; relTol 0.05; }
    U { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-10; relTol 0.1; }
}
SIMPLE
{
    nNonOrthogonalCorrectors 0;
    consistent yes;
    residualControl { p 1e-6; U 1e-6; }
}
relaxationFactors { equations { U 0.9; } }
""")


FOAM_BASHRC = "/usr/share/openfoam/etc/bashrc"  # Debian's OpenFOAM environment


def run(cmd, cwd, log):
    """An OpenFOAM utility inside its environment (Debian: source etc/bashrc first)."""
    script = f"source {FOAM_BASHRC} >/dev/null 2>&1; exec " + " ".join(cmd)
    with open(log, "w") as f:
        subprocess.run(["bash", "-c", script], cwd=cwd, stdout=f, stderr=subprocess.STDOUT, check=True)


def openfoam_cf(d):
    """Cf at the plate faces from wallShearStress (tau = -nu grad U . n on the wall, kinematic)."""
    times = sorted((p for p in d.iterdir() if re.fullmatch(r"[0-9.]+", p.name) and p.name != "0"),
                   key=lambda p: float(p.name))
    last = times[-1]
    wss = (last / "wallShearStress").read_text()
    block = wss[wss.index("plate"):]
    vals = re.search(r"value\s+nonuniform\s+List<vector>\s*(\d+)\s*\((.*?)\n\)", block, re.S)
    n = int(vals.group(1))
    vecs = re.findall(r"\(([-0-9.eE+]+) ([-0-9.eE+]+) ([-0-9.eE+]+)\)", vals.group(2))[:n]
    cfx = [-2.0 * float(v[0]) for v in vecs]  # wall shear stress points against the flow on the fluid side
    cc = (last / "C").read_text()
    block = cc[cc.index("plate"):]
    vals = re.search(r"value\s+nonuniform\s+List<vector>\s*(\d+)\s*\((.*?)\n\)", block, re.S)
    xs = [float(v[0]) for v in re.findall(r"\(([-0-9.eE+]+) ([-0-9.eE+]+) ([-0-9.eE+]+)\)", vals.group(2))[:n]]
    return xs, cfx, int(float(last.name))


def cf_error(xs, cf, re_l, fpp0):
    err = [c / (2.0 * fpp0 / math.sqrt(re_l * x)) - 1.0 for x, c in zip(xs, cf) if 0.1 < x < 0.9]
    return max(abs(e) for e in err), math.sqrt(sum(e * e for e in err) / len(err)), len(err)


def blasius_fpp0():
    for line in BLASIUS.read_text().splitlines():
        if line and not line.startswith("#") and not line.startswith("eta"):
            return float(line.split(",")[3])
    raise RuntimeError("no Blasius data")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--narwhal", default=str(ROOT / "build" / "solver" / "narwhal"))
    ap.add_argument("--out", default=str(ROOT / "reports" / "peer"))
    args = ap.parse_args()
    if not shutil.which("simpleFoam"):
        print("openfoam_flat_plate: simpleFoam not found (apt-get install openfoam; ci/nightly does)", file=sys.stderr)
        return 2
    out = Path(args.out)
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    with open(CASE, "rb") as f:
        case = tomllib.load(f)
    g, re_l = case["grid"], case["flow"]["reynolds"]
    fpp0 = blasius_fpp0()
    cells = (g["cells_runup"] + g["cells_plate"]) * g["cells_normal"]

    of = out / "openfoam"
    make_case(of, g, 1.0 / re_l)
    run(["blockMesh"], of, of / "log.blockMesh")
    t0 = time.monotonic()
    run(["simpleFoam"], of, of / "log.simpleFoam")
    t_of = time.monotonic() - t0
    run(["simpleFoam", "-postProcess", "-func", "wallShearStress", "-latestTime"], of, of / "log.wss")
    run(["postProcess", "-func", "writeCellCentres", "-latestTime"], of, of / "log.centres")
    xs, cf, iters = openfoam_cf(of)
    of_max, of_rms, n_of = cf_error(xs, cf, re_l, fpp0)

    results = {"cells": cells, "openfoam": {"wall_seconds": t_of, "iterations": iters, "cf_max_error": of_max,
                                            "cf_rms_error": of_rms, "faces": n_of}}
    for label, sets in (("narwhal_multigrid", ["solver.multigrid_levels=4", 'solver.multigrid_cycle="V"']),
                        ("narwhal_single_grid", [])):
        rd = out / label
        cmd = [args.narwhal, "run", str(CASE), "--out", str(rd)]
        for s in sets:
            cmd += ["--set", s]
        t0 = time.monotonic()
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        t = time.monotonic() - t0
        rows = [l.split(",") for l in (rd / "surface_plate.csv").read_text().splitlines()[2:]]
        n_max, n_rms, n_n = cf_error([float(r[0]) for r in rows], [float(r[8]) for r in rows], re_l, fpp0)
        runj = json.loads((rd / "run.json").read_text())
        results[label] = {"wall_seconds": t, "iterations": runj["iterations"], "cf_max_error": n_max,
                          "cf_rms_error": n_rms, "faces": n_n, "residual_drop": runj["residual_drop"]}
    best = results["narwhal_multigrid"]
    results["narwhal_reaches_openfoam_accuracy"] = best["cf_max_error"] <= of_max and best["cf_rms_error"] <= of_rms
    results["time_ratio_openfoam_over_narwhal"] = t_of / best["wall_seconds"]
    (out / "peer.json").write_text(json.dumps(results, indent=1))
    print(json.dumps(results, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
