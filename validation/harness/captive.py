"""Extractors of captive sweeps ([[sweep]] in a rung): the forces and moments of the runs of
one sweep in the captive-model literature's form, their symmetry, and the linear
derivatives fitted to them. Registered in schema.EXTRACT like the others.

Coefficients: X', Y', Z' = F / (1/2 rho U^2 L^2) and K', M', N' = M / (1/2 rho U^2 L^3)
in body axes (x forward, y starboard, z down; motion/grid_axes.hpp), about the run's
output.moment_centre, from run.json's forces[group].body_axes summed over the groups
named (the hull's and each appendage's walls make the vehicle's). L is the extraction's
`length` (default grid.length; the captive-model data use the length between
perpendiculars). Narwhal divides by output.reference_area and output.reference_length,
so a sweep's runs must set those to L^2 and L (checked).

The velocity components the derivatives are taken against follow the free stream set by
flow.angle_of_attack (alpha) and flow.drift_angle (beta), motion/grid_axes.hpp:
v' = v / U = -sin(beta), w' = w / U = sin(alpha) cos(beta).

A point whose steady run ended with its forces still swinging (a sweep's [sweep.unsteady]:
run.json force_span above its force_span) went on in physical time; its values are then
the continuation's means over the whole periods of the swing after its start's transient
(steps.csv, harness/periodic.py), its iteration band the standard error of that mean (from
the single periods' means), and its force span twice that error over the largest group's
force: the width within which the mean is known, as a steady run's span is the width
within which its forces still move.
"""
import json
import math

import numpy as np

from .compare import Curve
from .errors import HarnessError
from .periodic import period_average
from .schema import extractor

COMPONENTS = ("X", "Y", "Z", "K", "M", "N")
AGAINST = ("v", "w", "radians", "degrees")
STATISTICS = ("slope", "standard_error", "iteration_error")
# Body axes from the grid axes history.csv writes (motion/grid_axes.hpp: x_B = -x,
# y_B = -y, z_B = z; moments alike): component -> (history column suffix, sign).
BODY_AXES = {"X": ("cfx", -1.0), "Y": ("cfy", -1.0), "Z": ("cfz", 1.0),
             "K": ("cmx", -1.0), "M": ("cmy", -1.0), "N": ("cmz", 1.0)}


def _sweep(ctx, spec):
    name = spec.get("sweep")
    found = [s for s in ctx.rung.sweeps if s.id == name]
    if not found:
        raise HarnessError(f"rung '{ctx.rung.name}': no sweep {name!r}; sweeps: "
                           + (", ".join(s.id for s in ctx.rung.sweeps) or "none"))
    return found[0]


def _choice(spec, key, valid, default=None):
    value = spec.get(key, default)
    if value not in valid:
        raise HarnessError(f"extractor '{spec.get('kind')}': '{key}' must be one of {', '.join(valid)}, got {value!r}")
    return value


def _input_number(ctx, run_id, dotted, default):
    try:
        return float(ctx.input_value(run_id, dotted))
    except HarnessError:
        return default


def ended_unsteady(run_json, force_span, run_id):
    """Whether a steady run's forces were still swinging at its end (run.json force_span above
    `force_span`): the runner makes the point's continuation in physical time then, and the
    extractors take the point's values from it. The same test in both places."""
    span = run_json.get("force_span")
    if span is None:
        raise HarnessError(f"run.json of '{run_id}' has no force_span (solver.force_tolerance = 0?): whether the "
                           "point needs its continuation in physical time cannot be told")
    return float(span) > force_span


def _run_json(ctx, run_id):
    with open(ctx.run_dir(run_id) / "run.json") as f:
        return json.load(f)


def _continuation(ctx, sweep, run_id):
    """The id of the run a sweep point's values come from in physical time, or None when its
    steady run settled (or the sweep has no [sweep.unsteady])."""
    if not sweep.unsteady:
        return None
    if not ended_unsteady(_run_json(ctx, run_id), sweep.unsteady.force_span, run_id):
        return None
    later = sweep.unsteady.run_ids[sweep.run_ids.index(run_id)]
    if later not in ctx.run_dirs or not (ctx.run_dir(later) / "steps.csv").exists():
        raise HarnessError(f"point '{run_id}' ended with its forces unsteady (force span above "
                           f"{sweep.unsteady.force_span:g}), and its continuation in physical time '{later}' has no "
                           "steps.csv")
    return later


def _check_reference_lengths(ctx, run_id, length):
    """L (default grid.length), having checked that Narwhal divided by L^2 and L."""
    length = _input_number(ctx, run_id, "grid.length", 1.0) if length is None else float(length)
    area = _input_number(ctx, run_id, "output.reference_area", 1.0)
    arm = _input_number(ctx, run_id, "output.reference_length", 1.0)
    # To 1e-6: case files carry L and L^2 to six or seven digits.
    if not (math.isclose(area, length ** 2, rel_tol=1e-6) and math.isclose(arm, length, rel_tol=1e-6)):
        raise HarnessError(f"run '{run_id}': captive coefficients need output.reference_area = L^2 and "
                           f"output.reference_length = L (L = {length}); got {area} and {arm}")
    return length


def coefficient(ctx, run_id, component, groups, length=None):
    """A run's body-axes coefficient `component`, summed over the wall groups `groups`; L is
    `length` (default grid.length)."""
    _check_reference_lengths(ctx, run_id, length)
    forces = _run_json(ctx, run_id).get("forces", {})
    total = 0.0
    for g in groups:
        if g not in forces:
            raise HarnessError(f"run.json of '{run_id}' has no force group {g!r} (groups: {', '.join(forces)})")
        total += float(forces[g]["body_axes"][component])
    return total


def _read_rows(ctx, run_id, name):
    try:
        rows = np.genfromtxt(ctx.run_dir(run_id) / name, delimiter=",", names=True, comments="#")
    except (OSError, ValueError) as e:
        raise HarnessError(f"{name} of '{run_id}' cannot be read: {e}") from e
    return np.atleast_1d(rows)


def _force_history(ctx, run_id):
    """(time, column names, values) of a continuation's force coefficients (steps.csv: every
    group's cfx, cfy, cfz, cmx, cmy, cmz in grid axes)."""
    rows = _read_rows(ctx, run_id, "steps.csv")
    names = [n for n in rows.dtype.names or () if n.rsplit("_", 1)[-1] in {c for c, _ in BODY_AXES.values()}]
    if "time" not in (rows.dtype.names or ()) or not names:
        raise HarnessError(f"steps.csv of '{run_id}' has no time or no force coefficient columns")
    return np.asarray(rows["time"], float), names, np.column_stack([np.asarray(rows[n], float) for n in names])


def time_average(ctx, sweep, run_id):
    """(column names, PeriodAverage) of a continuation's force coefficients after the sweep's
    transient."""
    t, names, values = _force_history(ctx, run_id)
    return names, period_average(t, values, sweep.unsteady.discard)


def continuation_summary(ctx):
    """For the report: each sweep's rule for unsteady points (Unsteady) and the points that
    went on in physical time, with the periods their means are over and the history of the
    column whose rises bound them; a point that cannot be judged says why."""
    out = []
    for sweep in ctx.rung.sweeps:
        if not sweep.unsteady:
            continue
        points = []
        for rid in sweep.run_ids:
            if rid not in ctx.run_dirs:
                continue
            try:
                later = _continuation(ctx, sweep, rid)
                if later is None:
                    continue
                t, names, values = _force_history(ctx, later)
                average = period_average(t, values, sweep.unsteady.discard)
                points.append({"point": rid, "run": later, "periods": average.periods, "start": average.start,
                               "end": average.end, "force_span": _mean_force_span(names, average),
                               "history": {"column": names[average.reference], "t": t.tolist(),
                                           "y": values[:, average.reference].tolist()}})
            except HarnessError as e:
                points.append({"point": rid, "error": str(e)})
        out.append({"sweep": sweep.id, "force_span": sweep.unsteady.force_span, "discard": sweep.unsteady.discard,
                    "set": sweep.unsteady.set, "points": points})
    return out


def _weights(names, run_id, component, groups):
    """The weights that turn steps.csv's grid-axes columns into the body-axes coefficient
    summed over `groups`."""
    column, sign = BODY_AXES[component]
    missing = [f"{g}_{column}" for g in groups if f"{g}_{column}" not in names]
    if missing:
        raise HarnessError(f"steps.csv of '{run_id}' has no column {missing[0]!r}")
    return np.array([sign if n in {f"{g}_{column}" for g in groups} else 0.0 for n in names])


def point_coefficient(ctx, sweep, run_id, component, groups, length=None):
    """A sweep point's coefficient: its steady run's, or its continuation's mean over whole
    periods when the steady run ended unsteady."""
    later = _continuation(ctx, sweep, run_id)
    if later is None:
        return coefficient(ctx, run_id, component, groups, length)
    _check_reference_lengths(ctx, later, length)
    names, average = time_average(ctx, sweep, later)
    return float(average.means @ _weights(names, later, component, groups))


def point_band(ctx, sweep, run_id, component, groups):
    """A sweep point's iteration band: iteration_band of its steady run, or of a continuation
    the standard error of its mean (PeriodAverage.standard_error)."""
    later = _continuation(ctx, sweep, run_id)
    if later is None:
        return iteration_band(ctx, run_id, component, groups)
    names, average = time_average(ctx, sweep, later)
    return average.standard_error(_weights(names, later, component, groups))


def point_force_span(ctx, sweep, run_id):
    """A sweep point's force span: its steady run's (run.json), or of a continuation the
    largest width (twice the standard error) within which the mean of a force component of
    a group is known, over the largest group's mean force (as the solver's force span is
    the width within which the forces still move, over that force)."""
    later = _continuation(ctx, sweep, run_id)
    if later is None:
        from .extract import run_json  # here, not at the top: extract imports this module to register it
        return run_json(ctx, {"field": "force_span"}, run_id)
    return _mean_force_span(*time_average(ctx, sweep, later))


def _mean_force_span(names, average):
    """A continuation's force span from its PeriodAverage (point_force_span)."""
    forces = [i for i, n in enumerate(names) if n.rsplit("_", 1)[-1] in ("cfx", "cfy", "cfz")]
    groups = {names[i].rsplit("_", 1)[0] for i in forces}
    largest = max(math.sqrt(sum(average.means[names.index(f"{g}_{c}")] ** 2 for c in ("cfx", "cfy", "cfz")))
                  for g in groups)
    unit = np.eye(len(names))
    return float(max(2.0 * average.standard_error(unit[i]) for i in forces) / largest)


def iteration_band(ctx, run_id, component, groups):
    """Half the range of the coefficient over the run's last solver.force_window iterations
    (run.json settings; history.csv): the iteration's part of the point's uncertainty. Of a
    converged run it is below force_span times its largest force; of a point whose forces
    still swing it is the swing's half-amplitude. The iterations a retreat undid (run.json
    retreats: after back_to up to diverged_at) are not on the run's path and are left out."""
    data = _run_json(ctx, run_id)
    window = int(data.get("settings", {}).get("force_window", 0))
    if window < 2:
        raise HarnessError(f"run.json of '{run_id}' gives no settings.force_window of two or more iterations "
                           f"(got {window}): the iteration band needs it")
    column, sign = BODY_AXES[component]
    rows = _read_rows(ctx, run_id, "history.csv")
    names = rows.dtype.names or ()
    missing = [f"{g}_{column}" for g in groups if f"{g}_{column}" not in names]
    if missing:
        raise HarnessError(f"history.csv of '{run_id}' has no column {missing[0]!r}")
    undone = np.zeros(rows.size, bool)
    for r in data.get("retreats", []):
        undone |= (rows["iteration"] > r["back_to"]) & (rows["iteration"] <= r["diverged_at"])
    last = rows[~undone][-window:]
    total = sign * sum(np.asarray(last[f"{g}_{column}"], float) for g in groups)
    return 0.5 * float(np.ptp(total))


def _groups(spec):
    groups = spec.get("groups")
    if not isinstance(groups, list) or not groups or not all(isinstance(g, str) for g in groups):
        raise HarnessError(f"extractor '{spec.get('kind')}': 'groups' must be a non-empty list of wall groups "
                           f"(run.json forces), got {groups!r}")
    return groups


def _abscissa(ctx, run_id, value, against):
    """The variable a derivative is taken against, at one point of the sweep."""
    if against == "degrees":
        return value
    if against == "radians":
        return math.radians(value)
    alpha = math.radians(_input_number(ctx, run_id, "flow.angle_of_attack", 0.0))
    beta = math.radians(_input_number(ctx, run_id, "flow.drift_angle", 0.0))
    return -math.sin(beta) if against == "v" else math.sin(alpha) * math.cos(beta)


def _points(ctx, spec, against):
    """(sweep, abscissae, coefficients) of the sweep's runs, in the order of its values."""
    sweep = _sweep(ctx, spec)
    component = _choice(spec, "component", COMPONENTS)
    groups = _groups(spec)
    x, y = [], []
    for run_id, value in zip(sweep.run_ids, sweep.values):
        x.append(_abscissa(ctx, run_id, value, against))
        y.append(point_coefficient(ctx, sweep, run_id, component, groups, spec.get("length")))
    return sweep, np.array(x), np.array(y)


@extractor("run_coefficient", "component", "groups", "length")
def run_coefficient(ctx, spec, run_id):
    """One run's coefficient (a manoeuvring model's Z'_0, M'_0 and X'_uu from the straight
    run of a sweep)."""
    return coefficient(ctx, run_id, _choice(spec, "component", COMPONENTS), _groups(spec), spec.get("length"))


def _bands(ctx, spec, sweep):
    """Each point's iteration band (point_band), in the order of the sweep's values."""
    component, groups = _choice(spec, "component", COMPONENTS), _groups(spec)
    return np.array([point_band(ctx, sweep, rid, component, groups) for rid in sweep.run_ids])


@extractor("sweep_coefficient", "sweep", "component", "groups", "length")
def sweep_coefficient(ctx, spec, run_id):
    """The coefficient against the swept variable (its own values, e.g. degrees), each point
    with its iteration band."""
    sweep, x, y = _points(ctx, spec, "degrees")
    order = np.argsort(x)
    return Curve(x[order], y[order], f"{spec['component']}' vs {sweep.variable}", yerr=_bands(ctx, spec, sweep)[order])


def linear_fit(x, y):
    """Least-squares y = a + b x: (b, standard error of b). The standard error is that of
    the slope given the scatter about the line (n - 2 degrees of freedom); with two points
    it is undefined (nan)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    if x.size < 2 or np.ptp(x) == 0.0:
        raise HarnessError(f"a linear fit needs two or more distinct abscissae, got {x.tolist()}")
    xm = x.mean()
    sxx = float(np.sum((x - xm) ** 2))
    b = float(np.sum((x - xm) * (y - y.mean())) / sxx)
    a = float(y.mean() - b * xm)
    if x.size == 2:
        return b, math.nan
    residual = y - (a + b * x)
    return b, math.sqrt(float(np.sum(residual ** 2)) / (x.size - 2) / sxx)


@extractor("sweep_derivative", "sweep", "component", "groups", "length", "against", "max_angle", "statistic")
def sweep_derivative(ctx, spec, run_id):
    """The linear derivative of a coefficient (Y'v, N'v with against = "v"; Z'w, M'w with
    "w"; Y'delta with "radians"), fitted by least squares to the sweep's points whose swept
    value lies within max_angle (degrees) of zero. statistic = "standard_error" gives the
    fit's standard error instead of the slope (the scatter of the points about the line:
    non-linearity within the range and iteration error); "iteration_error" the most the
    slope can move when each point moves within its iteration band (iteration_band):
    sum |x_i - mean x| band_i / sum (x_i - mean x)^2, the bands taken as worst case, not
    as independent random errors, since an unconverged run's error is not random."""
    against = _choice(spec, "against", AGAINST)
    statistic = _choice(spec, "statistic", STATISTICS, "slope")
    sweep, x, y = _points(ctx, spec, against)
    limit = float(spec.get("max_angle", math.inf))
    inside = np.abs(np.array(sweep.values)) <= limit
    slope, error = linear_fit(x[inside], y[inside])
    if statistic == "iteration_error":
        dx = x[inside] - x[inside].mean()
        return float(np.sum(np.abs(dx) * _bands(ctx, spec, sweep)[inside]) / np.sum(dx ** 2))
    return slope if statistic == "slope" else error


@extractor("sweep_oddness", "sweep", "component", "groups", "length")
def sweep_oddness(ctx, spec, run_id):
    """max |C(a) + C(-a)| over the sweep's values a whose opposite is also swept (a = 0
    with itself: 2 |C(0)|). A symmetric configuration's side force, roll and yaw moment are
    odd in the drift angle: this is zero up to discretization asymmetry and iteration error."""
    sweep, x, y = _points(ctx, spec, "degrees")
    by_value = dict(zip(sweep.values, y))
    pairs = [abs(c + by_value[-a]) for a, c in by_value.items() if -a in by_value]
    if not pairs:
        raise HarnessError(f"sweep '{sweep.id}': no value has its opposite swept (values {list(sweep.values)})")
    return max(pairs)


@extractor("sweep_largest", "sweep", "field")
def sweep_largest(ctx, spec, run_id):
    """The largest value of a run.json number over the sweep's points: with field =
    "force_span", how far from steady the least steady point's forces still were (of a
    point continued in physical time, the width within which its mean is known: point_force_span)."""
    from .extract import run_json  # here, not at the top: extract imports this module to register it
    sweep = _sweep(ctx, spec)
    if spec.get("field") == "force_span":
        return max(point_force_span(ctx, sweep, rid) for rid in sweep.run_ids)
    return max(run_json(ctx, {"field": spec.get("field")}, rid) for rid in sweep.run_ids)


@extractor("sweep_magnitude", "sweep", "component", "groups", "length")
def sweep_magnitude(ctx, spec, run_id):
    """max |C| over the sweep's runs: a component that symmetry makes zero at every point
    (a port/starboard-symmetric vehicle's side force, roll and yaw moments in pitch)."""
    _, _, y = _points(ctx, spec, "degrees")
    return float(np.max(np.abs(y)))
