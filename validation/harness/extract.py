"""Extractors: turn a rung's run outputs (history.csv, surface_*.csv, run.json,
solution.cgns, restart.h5 never) into the numbers and curves its checks compare.
The screen log is never read."""
import csv
import json
import math

import numpy as np

from . import exact
from . import body  # noqa: F401  (registers recirculation_length, surface_taps)
from . import captive  # noqa: F401  (registers sweep_coefficient, sweep_derivative, sweep_oddness)
from . import duct  # noqa: F401  (registers duct_flow)
from . import motion  # noqa: F401  (registers oscillation_force)
from . import autopilot  # noqa: F401  (registers depth_change, control_extreme)
from . import pmm  # noqa: F401  (registers pmm_derivative)
from . import propulsor  # noqa: F401  (registers propulsor_momentum_balance, slipstream_peak)
from . import settings  # noqa: F401  (registers settings_differing)
from .compare import Curve, Family
from .errors import HarnessError
from .schema import EXTRACT, Declared, extractor
from .solution import read_solution


def read_csv(path):
    with open(path) as f:
        rows = [r for r in csv.reader(line for line in f if not line.startswith("#"))]
    if not rows:
        raise HarnessError(f"{path} is empty")
    names = rows[0]
    data = np.array([[float(v) for v in r] for r in rows[1:]]) if len(rows) > 1 else np.zeros((0, len(names)))
    return {n: data[:, i] for i, n in enumerate(names)}


class Context:
    """What a rung's runs produced: output directory and effective input per run id."""

    def __init__(self, rung, run_dirs, inputs, reference_root=None):
        self.rung, self.run_dirs, self.inputs = rung, run_dirs, inputs
        self.reference_root = reference_root  # for extractors that draw reference fields beside theirs
        self._solutions = {}

    def run_dir(self, run_id):
        if run_id not in self.run_dirs:
            raise HarnessError(f"rung '{self.rung.name}': no run '{run_id}' in this tier")
        return self.run_dirs[run_id]

    def run_code(self, run_id):
        """The code that made a run: "narwhal", or a peer code's name."""
        return next((r.code for r in self.rung.runs if r.id == run_id), "narwhal")

    def solution(self, run_id):
        if run_id not in self._solutions:
            self._solutions[run_id] = read_solution(self.run_dir(run_id) / "solution.cgns")
        return self._solutions[run_id]

    def input_value(self, run_id, dotted):
        node = self.inputs[run_id]
        index = None
        if dotted.endswith("]"):
            dotted, index = dotted[:-1].split("[")
        for part in dotted.split("."):
            if not isinstance(node, dict) or part not in node:
                raise HarnessError(f"rung '{self.rung.name}': run '{run_id}' input has no key '{dotted}'")
            node = node[part]
        return node[int(index)] if index is not None else node

    def family_runs(self, name):
        runs = [r for r in self.rung.runs if r.family == name and r.id in self.run_dirs]
        if len(runs) < 2:
            raise HarnessError(f"rung '{self.rung.name}': family '{name}' has {len(runs)} run(s) in this tier")
        return runs

    def grid_spacing(self, run):
        """The run's h: as declared, or N^(-1/3) of the cells its run.json reports."""
        if run.h != "cells":
            return run.h
        path = self.run_dir(run.id) / "run.json"
        try:
            with open(path) as f:
                cells = json.load(f)["cells"]
        except (OSError, ValueError, KeyError) as e:
            raise HarnessError(f"run '{run.id}': h = \"cells\" needs the cell count of {path}: {e}") from e
        return float(cells) ** (-1.0 / 3.0)

    def resolve(self, run_id, value):
        """'input:<dotted.key>' strings are looked up in the run's input."""
        if isinstance(value, str) and value.startswith("input:"):
            return self.input_value(run_id, value[len("input:"):])
        return value


def _need(spec, key, what):
    if key not in spec:
        raise HarnessError(f"extractor '{spec.get('kind')}' needs '{key}' ({what})")
    return spec[key]


@extractor("surface", "group", "y", "x", "x_min", "x_max")
def surface(ctx, spec, run_id):
    group = _need(spec, "group", "the wall group")
    path = ctx.run_dir(run_id) / f"surface_{group}.csv"
    if not path.exists():
        raise HarnessError(f"run '{run_id}' wrote no {path.name}")
    t = read_csv(path)
    xn, yn = spec.get("x", "x"), _need(spec, "y", "the column to compare")
    for n in (xn, yn):
        if n not in t:
            raise HarnessError(f"{path.name} has no column '{n}'")
    x, y = t[xn], t[yn]
    lo, hi = spec.get("x_min", -np.inf), spec.get("x_max", np.inf)
    keep = (x > lo) & (x < hi)
    return Curve(x[keep], y[keep], f"{yn}({xn})")


@extractor("surface_at", "group", "y", "x", "at")
def surface_at(ctx, spec, run_id):
    """One surface column interpolated (linearly in x) to the station `at`."""
    c = surface(ctx, {k: v for k, v in spec.items() if k not in ("x_min", "x_max")}, run_id)
    x0 = float(_need(spec, "at", "the station"))
    if not c.x.min() <= x0 <= c.x.max():
        raise HarnessError(f"surface_at: x = {x0} lies outside the wall faces [{c.x.min()}, {c.x.max()}]")
    return float(np.interp(x0, c.x, c.y))


@extractor("surface_largest", "groups", "column")
def surface_largest(ctx, spec, run_id):
    """The largest value of a surface column over the faces of several wall groups (the
    wall cells' y+ on a hull and each of its appendages)."""
    groups = _need(spec, "groups", "the wall groups")
    col = _need(spec, "column", "the surface column")
    if not isinstance(groups, list) or not groups:
        raise HarnessError("surface_largest: 'groups' must be a non-empty list of wall groups")
    return max(float(np.max(surface(ctx, {"group": g, "y": col}, run_id).y)) for g in groups)


@extractor("wall_units", "x", "reynolds", "group", "yplus_min", "yplus_max")
def wall_units(ctx, spec, run_id):
    """u+ against y+ at station x of a single-block plate: u_tau = sqrt(|Cf|/2) from the
    wall shear interpolated there (U = 1, rho = 1), y+ = Re u_tau y, u+ = u/u_tau."""
    zones = ctx.solution(run_id)
    if len(zones) != 1:
        raise HarnessError("wall_units extraction expects a single-block plate grid")
    x0 = float(_need(spec, "x", "the streamwise station"))
    re = float(ctx.resolve(run_id, spec.get("reynolds", "input:flow.reynolds")))
    cf = surface_at(ctx, {"group": spec.get("group", "plate"), "y": "cf_x", "at": x0}, run_id)
    utau = math.sqrt(abs(cf) / 2.0)
    y, u, _ = _column_at(zones[0], x0)
    yp, up = re * utau * y, u / utau
    keep = (yp >= float(spec.get("yplus_min", 0.0))) & (yp <= float(spec.get("yplus_max", np.inf)))
    return Curve(yp[keep], up[keep], "u+(y+)")


@extractor("cf_vs_retheta", "reynolds", "group", "re_min", "re_max")
def cf_vs_retheta(ctx, spec, run_id):
    """Skin friction against the momentum-thickness Reynolds number along a single-block
    plate: theta = int u/U_e (1 - u/U_e) dy per wall-normal column up to the edge, where
    u first reaches 99.5 % of the column's largest value (U_e = u there; zero pressure
    gradient); returns Cf(Re_theta) inside [re_min, re_max]."""
    zones = ctx.solution(run_id)
    if len(zones) != 1:
        raise HarnessError("cf_vs_retheta expects a single-block plate grid")
    z = zones[0]
    re = float(ctx.resolve(run_id, spec.get("reynolds", "input:flow.reynolds")))
    wall = surface(ctx, {"group": spec.get("group", "plate"), "y": "cf_x"}, run_id)
    xc = z.centres[0, 0, :, 0]
    ret, cf = [], []
    for i, x0 in enumerate(xc):
        if x0 <= wall.x.min() or x0 >= wall.x.max():
            continue
        u = z.fields["u"][0, :, i]
        dy = np.diff(z.x[0, :, i + 1, 1])
        # Edge: the first cell reaching 99.5 % of the column's largest u; beyond it the
        # far-field's own small velocity variations would add to theta.
        je = int(np.argmax(u >= 0.995 * u.max()))
        ue = float(u[je])
        r = np.minimum(u[: je + 1] / ue, 1.0)
        theta = float(np.sum(r * (1.0 - r) * dy[: je + 1]))
        ret.append(re * ue * theta)
        cf.append(float(np.interp(x0, wall.x, wall.y)) / ue ** 2)
    ret, cf = np.array(ret), np.array(cf)
    keep = (ret >= float(spec.get("re_min", 0.0))) & (ret <= float(spec.get("re_max", np.inf)))
    if not keep.any():
        raise HarnessError(f"cf_vs_retheta: no station of '{run_id}' lies in the Re_theta range")
    return Curve(ret[keep], cf[keep], "Cf(Re_theta)")


@extractor("run_json", "field")
def run_json(ctx, spec, run_id):
    """A number of run.json; `field` may walk into its tables with dots (trim.weight)."""
    with open(ctx.run_dir(run_id) / "run.json") as f:
        data = json.load(f)
    field = _need(spec, "field", "a run.json field")
    node = data
    for part in field.split("."):
        if not isinstance(node, dict) or part not in node:
            raise HarnessError(f"run.json of '{run_id}' has no field '{field}'")
        node = node[part]
    return float(node)


@extractor("history_last", "column", "columns")
def history_last(ctx, spec, run_id):
    """The last row's value of one column, or the sum of several (`columns`: the forces
    on an appended hull's walls, one group each, make the vehicle's)."""
    t = read_csv(ctx.run_dir(run_id) / "history.csv")
    if ("column" in spec) == ("columns" in spec):
        raise HarnessError("extractor 'history_last' needs 'column' (a history.csv column) or 'columns' (a list "
                           "of them, summed), not both")
    cols = spec["columns"] if "columns" in spec else [spec["column"]]
    if not isinstance(cols, list) or not cols:
        raise HarnessError("extractor 'history_last': 'columns' must be a non-empty list of history.csv columns")
    for col in cols:
        if col not in t:
            raise HarnessError(f"history.csv of '{run_id}' has no column '{col}' (columns: {', '.join(t)})")
        if t[col].size == 0:
            raise HarnessError(f"history.csv of '{run_id}' has no rows")
    return float(sum(t[col][-1] for col in cols))


@extractor("field_error", "exact", "params", "variable", "norm", "remove_mean")
def field_error(ctx, spec, run_id):
    name = _need(spec, "exact", "an exact solution: " + ", ".join(exact.SOLUTIONS))
    if name not in exact.SOLUTIONS:
        raise HarnessError(f"unknown exact solution {name!r}; valid: {', '.join(exact.SOLUTIONS)}")
    params = {k: float(ctx.resolve(run_id, v)) for k, v in spec.get("params", {}).items()}
    var = spec.get("variable", "u")
    norm = spec.get("norm", "l2")
    num, den, worst = 0.0, 0.0, 0.0
    for z in ctx.solution(run_id):
        c = z.centres
        ex = exact.SOLUTIONS[name](c[..., 0], c[..., 1], c[..., 2], **params)
        d = z.fields[var] - ex[var]
        if spec.get("remove_mean", False):
            d = d - np.sum(d * z.volumes) / np.sum(z.volumes)
        num += float(np.sum(d * d * z.volumes))
        den += float(np.sum(z.volumes))
        worst = max(worst, float(np.max(np.abs(d))))
    if norm == "l2":
        return math.sqrt(num / den)
    if norm == "max":
        return worst
    raise HarnessError(f"field_error: norm must be l2 or max, got {norm!r}")


def _column_at(zone, x0):
    """Wall-normal column (j) of the single 2-D zone interpolated to x = x0."""
    xc = zone.centres[0, 0, :, 0]
    i = int(np.searchsorted(xc, x0)) - 1
    if i < 0 or i + 1 >= xc.size:
        raise HarnessError(f"x = {x0} lies outside the cell centres [{xc[0]}, {xc[-1]}]")
    w = (x0 - xc[i]) / (xc[i + 1] - xc[i])
    y = (1 - w) * zone.centres[0, :, i, 1] + w * zone.centres[0, :, i + 1, 1]
    u = (1 - w) * zone.fields["u"][0, :, i] + w * zone.fields["u"][0, :, i + 1]
    ynode = zone.x[0, :, i + 1, 1]  # tensor-product plate grid: node heights shared by the columns
    return y, u, ynode


@extractor("boundary_layer", "x", "reynolds", "eta_edge", "quantity", "eta_max")
def boundary_layer(ctx, spec, run_id):
    """u/U_e against eta = y sqrt(Re/x) at x (a Curve), or the displacement thickness
    delta* = int (1 - u/U_e) dy up to eta_edge, with U_e = u at eta_edge."""
    zones = ctx.solution(run_id)
    if len(zones) != 1:
        raise HarnessError("boundary_layer extraction expects a single-block plate grid")
    x0 = float(_need(spec, "x", "the streamwise station"))
    re = float(ctx.resolve(run_id, spec.get("reynolds", "input:flow.reynolds")))
    eta_edge = float(spec.get("eta_edge", 15.0))
    y, u, ynode = _column_at(zones[0], x0)
    eta = y * math.sqrt(re / x0)
    je = int(np.searchsorted(eta, eta_edge))
    if je >= eta.size:
        raise HarnessError(f"the grid ends below eta = {eta_edge} at x = {x0}")
    ue = u[je - 1] + (u[je] - u[je - 1]) * (eta_edge - eta[je - 1]) / (eta[je] - eta[je - 1])
    if spec.get("quantity", "profile") == "profile":
        keep = eta <= float(spec.get("eta_max", 8.0))
        return Curve(eta[keep], u[keep] / ue, "u/U_e(eta)")
    if spec["quantity"] == "displacement_thickness":
        dy = np.diff(ynode)[:je]
        return float(np.sum((1.0 - u[:je] / ue) * dy))
    raise HarnessError("boundary_layer: quantity must be 'profile' or 'displacement_thickness'")


@extractor("duct", "quantity", "body_force", "reynolds", "hydraulic_diameter")
def duct(ctx, spec, run_id):
    """Fully developed duct flow periodic in x: u_max/u_bulk, or f Re with the Darcy
    friction factor f = G D_h / (u_b^2 / 2) from the driving body force G."""
    zones = ctx.solution(run_id)
    area, flux, umax = 0.0, 0.0, 0.0
    for z in zones:
        if z.x.shape[2] < 2:
            continue
        # Cross-section areas from the cell volumes divided by the streamwise length.
        dx = z.x[1:, 1:, 1:, 0] - z.x[1:, 1:, :-1, 0]
        a = z.volumes / np.abs(dx)
        area += float(np.sum(a[..., 0]))
        flux += float(np.sum(a[..., 0] * z.fields["u"][..., 0]))
        umax = max(umax, float(np.max(z.fields["u"])))
    ub = flux / area
    q = spec.get("quantity", "umax_over_ubulk")
    if q == "umax_over_ubulk":
        return umax / ub
    if q == "f_re":
        g = float(ctx.resolve(run_id, spec.get("body_force", "input:flow.body_force[0]")))
        re = float(ctx.resolve(run_id, spec.get("reynolds", "input:flow.reynolds")))
        dh = float(_need(spec, "hydraulic_diameter", "D_h in reference lengths"))
        return 2.0 * g * dh * dh * re / ub
    raise HarnessError("duct: quantity must be umax_over_ubulk or f_re")


@extractor("history_steadiness", "column", "window")
def history_steadiness(ctx, spec, run_id):
    """Largest relative change of a history column over the last `window` iterations
    (e.g. a force coefficient: 1e-5 means steady to 5 digits)."""
    t = read_csv(ctx.run_dir(run_id) / "history.csv")
    col = _need(spec, "column", "a history.csv column")
    if col not in t:
        raise HarnessError(f"history.csv of '{run_id}' has no column '{col}' (columns: {', '.join(t)})")
    window = int(spec.get("window", 50))
    v = t[col]
    if v.size < window + 1:
        raise HarnessError(f"history.csv of '{run_id}' has {v.size} rows, fewer than the window {window} + 1")
    last = v[-1]
    if last == 0.0:
        raise HarnessError(f"'{col}' of '{run_id}' ends at zero: a relative change is undefined")
    return float(np.max(np.abs(v[-window - 1:] - last)) / abs(last))


@extractor("history_difference", "run_a", "run_b", "from_iteration")
def history_difference(ctx, spec, run_id):
    """Largest relative difference between two runs' history rows (wall time excluded),
    over the iterations both have: 0 when a restarted run repeats an uninterrupted one."""
    a = read_csv(ctx.run_dir(_need(spec, "run_a", "the uninterrupted run")) / "history.csv")
    b = read_csv(ctx.run_dir(_need(spec, "run_b", "the restarted run")) / "history.csv")
    ia, ib = a["iteration"], b["iteration"]
    common = np.intersect1d(ia, ib)
    first = float(spec.get("from_iteration", 1))
    common = common[common >= first]
    if common.size == 0:
        raise HarnessError("history_difference: the runs share no iterations")
    worst = 0.0
    for name in a:
        if name in ("wall_s", "iteration") or name not in b:
            continue
        va = a[name][np.isin(ia, common)]
        vb = b[name][np.isin(ib, common)]
        scale = np.maximum(np.abs(va), 1e-300)
        worst = max(worst, float(np.max(np.abs(va - vb) / scale)))
    return worst


def _two_scalars(ctx, spec, kind, a_is, b_is):
    """The scalar extractions spec['a'] and spec['b'] of a two-operand extractor."""
    a, b = extract(ctx, _need(spec, "a", a_is)), extract(ctx, _need(spec, "b", b_is))
    if isinstance(a, (Curve, Family)) or isinstance(b, (Curve, Family)):
        raise HarnessError(f"{kind} needs two scalar extractions")
    return float(a), float(b)


@extractor("ratio", "a", "b")
def ratio(ctx, spec, run_id):
    """Ratio of two scalar extractions, e.g. single-grid over multigrid wall time."""
    a, b = _two_scalars(ctx, spec, "ratio", "the numerator extraction", "the denominator")
    if b == 0.0:
        raise HarnessError("ratio: the denominator is zero")
    return a / b


@extractor("difference", "a", "b")
def difference(ctx, spec, run_id):
    """a - b of two scalar extractions, e.g. an appended hull's resistance less the bare
    hull's (the appendages' increment)."""
    a, b = _two_scalars(ctx, spec, "difference", "the minuend extraction", "the subtrahend")
    return a - b


@extractor("dimensional", "of", "density", "speed", "area")
def dimensional(ctx, spec, run_id):
    """A force coefficient (a scalar extraction) in newtons: C 1/2 rho U^2 A, with the
    density (kg/m^3), speed (m/s) and reference area (m^2) of the model the rung
    stands for. Over a grid family the inner extraction reads each run in turn."""
    inner = dict(_need(spec, "of", "the coefficient's extraction"))
    if run_id:
        inner["run"] = run_id
    c = extract(ctx, inner)
    if isinstance(c, (Curve, Family)):
        raise HarnessError("dimensional needs a scalar coefficient")
    q = {k: float(_need(spec, k, f"the model's {k} (SI)")) for k in ("density", "speed", "area")}
    return float(c) * 0.5 * q["density"] * q["speed"] ** 2 * q["area"]


@extractor("curve_difference", "a", "b", "relative")
def curve_difference(ctx, spec, run_id):
    """Largest |a - b| between two curves sampled at the same points (e.g. Cf of two runs);
    with relative = true divided by max |a|."""
    a, b = extract(ctx, _need(spec, "a", "the first curve")), extract(ctx, _need(spec, "b", "the second curve"))
    if not isinstance(a, Curve) or not isinstance(b, Curve):
        raise HarnessError("curve_difference needs two curves")
    if a.x.shape != b.x.shape or np.max(np.abs(a.x - b.x)) > 1e-12 * max(1.0, np.max(np.abs(a.x))):
        raise HarnessError("curve_difference: the curves are not sampled at the same points")
    d = float(np.max(np.abs(a.y - b.y)))
    if spec.get("relative", False):
        d /= max(float(np.max(np.abs(a.y))), 1e-300)
    return d


@extractor("final_force_difference", "run_a", "run_b")
def final_force_difference(ctx, spec, run_id):
    """Largest difference between two runs' last history rows over the force and moment
    columns, relative to the largest |coefficient| of the first run's row (a zero
    component, such as the side force of a 2-D plate, is not divided by itself)."""
    a = read_csv(ctx.run_dir(_need(spec, "run_a", "the reference run")) / "history.csv")
    b = read_csv(ctx.run_dir(_need(spec, "run_b", "the compared run")) / "history.csv")
    cols = [n for n in a if any(n.endswith(f"_{c}") for c in ("cfx", "cfy", "cfz", "cmx", "cmy", "cmz"))]
    if not cols:
        raise HarnessError("final_force_difference: the history has no force columns")
    missing = [n for n in cols if n not in b]
    if missing:
        raise HarnessError(f"final_force_difference: run_b lacks {', '.join(missing)}")
    scale = max(max(abs(float(a[n][-1])) for n in cols), 1e-300)
    return max(abs(float(a[n][-1]) - float(b[n][-1])) for n in cols) / scale


def extract(ctx, spec):
    kind = spec.get("kind")
    if kind not in EXTRACT:
        raise HarnessError(f"unknown extractor kind {kind!r}; valid: {', '.join(EXTRACT)}")
    spec = Declared(spec)
    if "family" in spec:
        runs = ctx.family_runs(spec["family"])
        return Family([ctx.grid_spacing(r) for r in runs], [EXTRACT[kind][0](ctx, spec, r.id) for r in runs],
                      spec["family"])
    return EXTRACT[kind][0](ctx, spec, spec.get("run", ""))
