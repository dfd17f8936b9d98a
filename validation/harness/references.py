"""Reference values and curves, always read from files under reference_data/."""
import math

import numpy as np

from .compare import Curve
from .errors import HarnessError
from .reference import ReferenceFile


def _blasius_eta_minus_f(ref):
    eta, f = ref.column("eta"), ref.column("f")
    return float(eta[-1] - f[-1])  # f ~ eta - delta1 coefficient far outside the layer


def _munk_moment(ref, p):
    rows = ref.rows_where({"AR_a_over_b": p["ratio"]})
    if len(rows) != 1:
        raise HarnessError(f"munk_moment: {len(rows)} rows of aspect ratio {p['ratio']}, expected one")
    k1, k2 = float(ref.column("k1_axial", rows)[0]), float(ref.column("k2_lateral", rows)[0])
    volume = math.pi * p["length"] ** 3 / (6.0 * p["ratio"] ** 2)
    a = math.radians(p["alpha_deg"])
    return 2.0 * (k2 - k1) * volume * math.sin(a) * math.cos(a) / (p["area_ref"] * p["length_ref"])


def _release_acceleration(ref, p):
    rows = ref.rows_where({"AR_a_over_b": p["ratio"]})
    if len(rows) != 1:
        raise HarnessError(f"release_acceleration: {len(rows)} rows of aspect ratio {p['ratio']}, expected one")
    k = float(ref.column("k2_lateral" if p.get("lateral", 0.0) else "k1_axial", rows)[0])
    r = p["density_ratio"]
    return (r - 1.0) / (r + k)


def _fall_velocity_standard_drag(ref, p):
    """The vertical velocity (negative: falling, in u_g) at which the standard drag curve's
    drag carries a sphere's weight less its buoyancy: U^2 C_D(Ga U) = 4/3 in units D and
    u_g = sqrt((rho_s/rho_f - 1) g D), where Re = Ga U. C_D is interpolated in log-log
    between the table's Reynolds numbers; U^2 C_D grows with U, so bisection finds it."""
    re, cd = ref.column("Re"), ref.column("CD_CliftGraceWeber")
    ga = p["galileo"]

    def excess(u):
        r = ga * u
        if not re[0] <= r <= re[-1]:
            raise HarnessError(f"fall_velocity_standard_drag: Re = {r:g} at Ga = {ga:g} is outside the table "
                               f"({re[0]:g} to {re[-1]:g})")
        return u * u * math.exp(np.interp(math.log(r), np.log(re), np.log(cd))) - 4.0 / 3.0

    lo, hi = re[0] / ga, re[-1] / ga
    if excess(lo) > 0.0 or excess(hi) < 0.0:
        raise HarnessError(f"fall_velocity_standard_drag: no terminal velocity within the table at Ga = {ga:g}")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if excess(mid) < 0.0 else (lo, mid)
    return -0.5 * (lo + hi)


def _potential_flow_cp(ref):
    """Cp(x/L) of potential flow about a body of revolution given by its offsets (columns
    x_over_LOA, r_over_LOA from nose to tail, suboff_hull_offsets.csv): a panel on each
    interval between offsets (harness/potential_flow.py)."""
    from .potential_flow import surface_cp
    xm, _, cp = surface_cp(ref.column("x_over_LOA"), ref.column("r_over_LOA"))
    return Curve(xm, cp, "potential flow about the offsets (vortex-ring panels)")


DERIVED = {
    # Cf(x) = 2 f''(0) / sqrt(Re x)
    "blasius_cf": lambda ref, p: (lambda x, c=2.0 * float(ref.column("fpp")[0]), re=p["reynolds"]:
                                  c / math.sqrt(re * x)),
    # one-sided drag of a plate of unit length: C_D = (1/L) int Cf dx = 4 f''(0) / sqrt(Re L)
    "blasius_drag": lambda ref, p: 4.0 * float(ref.column("fpp")[0]) / math.sqrt(p["reynolds"]),
    # delta*(x) = lim(eta - f) x / sqrt(Re x)
    "blasius_delta_star": lambda ref, p: _blasius_eta_minus_f(ref) * p["x"] / math.sqrt(p["reynolds"] * p["x"]),
    # Munk moment of a prolate spheroid at incidence, nose up, as the solver's moment
    # coefficient 2 M / (A_ref L_ref): M = (k2 - k1) V sin a cos a (rho U^2 L^3 units), the
    # k's from the row of the body's aspect ratio, V = pi L^3 / (6 ratio^2).
    "munk_moment": lambda ref, p: _munk_moment(ref, p),
    # inviscid surface pressure of a body of revolution at zero incidence
    "potential_flow_cp": lambda ref, p: _potential_flow_cp(ref),
    # A body released from rest in still fluid: its acceleration over g, (r - 1) / (r + k),
    # r the density ratio, k Lamb's added-mass coefficient along the fall (k1 with the axis
    # vertical, lateral = 0; k2 across it, lateral = 1) from the row of the aspect ratio.
    "release_acceleration": lambda ref, p: _release_acceleration(ref, p),
    # A sphere's terminal fall velocity at Galileo number Ga (params galileo) on the
    # standard drag curve (column CD_CliftGraceWeber of sphere_drag_correlations.csv).
    "fall_velocity_standard_drag": lambda ref, p: _fall_velocity_standard_drag(ref, p),
    # u/U_e = f'(eta)
    "blasius_profile": lambda ref, p: Curve(ref.column("eta"), ref.column("fp"), "Blasius f'(eta)"),
}


def _column_value(ref, spec, where):
    """One value of spec['column']: the row `where` selects (exactly one), else spec['row']."""
    col = ref.column(spec["column"], ref.rows_where(where) if where is not None else None)
    if where is not None and col.size != 1:
        raise HarnessError(f"reference '{spec['file']}': {col.size} rows match {where}, expected one")
    row = int(spec.get("row", 0))
    if not -col.size <= row < col.size:
        raise HarnessError(f"reference '{spec['file']}': row {row} out of range ({col.size} rows)")
    return float(col[row])


def resolve_reference(ctx, spec, root, run_id_for_inputs=None):
    """Returns (value, description). Missing files, columns or header lines are errors."""
    if not spec:
        return None, ""
    if "extract" in spec:
        from .extract import extract  # extract imports this module
        run = spec["extract"].get("run", "")
        return extract(ctx, spec["extract"]), f"run '{run}' of this rung ({ctx.run_code(run)})"
    if "file" not in spec:
        raise HarnessError("a reference needs 'file' (a path under reference_data/)")
    ref = ReferenceFile(root, spec["file"])
    desc = f"{spec['file']} — {ref.citation()}"
    if "derive" in spec:
        name = spec["derive"]
        if name not in DERIVED:
            raise HarnessError(f"unknown derived reference {name!r}; valid: {', '.join(DERIVED)}")
        params = {k: float(ctx.resolve(run_id_for_inputs, v)) if ctx else float(v)
                  for k, v in spec.get("params", {}).items()}
        return DERIVED[name](ref, params), desc
    if "header" in spec:
        return ref.header_value(spec["header"]), desc
    if "x" in spec and "y" in spec:
        rows = ref.rows_where(spec["where"]) if "where" in spec else None
        y = ref.column(spec["y"], rows)
        # x = "#row": the rows' order numbers, for tables of points (pressure taps) that
        # an extractor enumerates the same way (body.surface_taps).
        x = np.arange(y.size, dtype=float) if spec["x"] == "#row" else ref.column(spec["x"], rows)
        return Curve(x, y, spec["y"]), desc
    if "column" in spec:
        value = _column_value(ref, spec, spec.get("where"))
        if "minus" in spec:
            if "where" not in spec:
                raise HarnessError(f"reference '{spec['file']}': 'minus' needs 'where' (the row it is subtracted from)")
            value -= _column_value(ref, spec, spec["minus"])
            desc += f" ({spec['column']} where {spec['where']} minus where {spec['minus']})"
        return value, desc
    raise HarnessError(f"reference '{spec['file']}': say what to take (column, header, x/y or derive)")
