"""Extractors of flow around a body of revolution on narwhal's six-block grid
(solver/mesh/body_of_revolution.hpp): the axis x, the nose at x = 0, the rear pole
where the block 'tail' closes on the axis."""
import numpy as np

from .compare import Curve
from .errors import HarnessError
from .reference import ReferenceFile
from .schema import extractor


def axis_velocity(zone):
    """u along the axis behind the body: the mean of the four cells around the 'tail'
    block's centre grid line (the axis, node (n/2, n/2) of its square), per layer
    from the wall out. Returns (x of the rear pole, x of the layers, u)."""
    nk, nj, ni = zone.fields["u"].shape
    if ni != nj or ni % 2:
        raise HarnessError("axis extraction needs the tail block's square with an even cell count per side")
    m = ni // 2
    u = zone.fields["u"][:, m - 1:m + 1, m - 1:m + 1].mean(axis=(1, 2))
    x = zone.centres[:, m - 1:m + 1, m - 1:m + 1, 0].mean(axis=(1, 2))
    axis_nodes = zone.x[:, m, m, :]
    if np.max(np.abs(axis_nodes[:, 1:])) > 1e-9 * max(1.0, float(np.max(np.abs(axis_nodes[:, 0])))):
        raise HarnessError("axis extraction: the tail block's centre line is not the x axis")
    return float(axis_nodes[0, 0]), x, u


@extractor("recirculation_length", "diameter")
def recirculation_length(ctx, spec, run_id):
    """Length of the recirculation bubble behind the body, from the rear pole to where
    u on the axis turns positive, in diameters (0 without a bubble)."""
    tails = [z for z in ctx.solution(run_id) if z.name == "tail"]
    if len(tails) != 1:
        raise HarnessError(f"recirculation_length: run '{run_id}' has no single block 'tail' (a body-of-revolution grid)")
    rear, x, u = axis_velocity(tails[0])
    diameter = float(spec.get("diameter", 1.0))
    length = 0.0
    if u[0] < 0.0:
        turn = np.nonzero(u >= 0.0)[0]
        if turn.size == 0:
            raise HarnessError(f"recirculation_length: u < 0 along the whole axis of '{run_id}'")
        k = int(turn[0])
        w = -u[k - 1] / (u[k] - u[k - 1])
        length = ((1 - w) * x[k - 1] + w * x[k] - rear) / diameter
    return length


def _tap_rows(ctx, taps):
    """Rows of a tap table (reference_data file, optional `where`), as in the reference
    spec whose x is "#row": both sides enumerate the same taps in the same order."""
    if not isinstance(taps, dict) or "file" not in taps:
        raise HarnessError("surface_taps: 'taps' needs {file, where, x, phi}: the tap table under reference_data/")
    ref = ReferenceFile(ctx.reference_root, taps["file"])
    rows = ref.rows_where(taps["where"]) if "where" in taps else list(range(len(ref.rows)))
    return ref.column(taps.get("x", "x_over_L"), rows), ref.column(taps.get("phi", "phi_deg"), rows)


def run_surface(ctx, spec, run_id):
    """The run's surface table of the extraction's wall group (default "body")."""
    from .extract import read_csv  # extract imports this module to register it
    path = ctx.run_dir(run_id) / f"surface_{spec.get('group', 'body')}.csv"
    if not path.exists():
        raise HarnessError(f"run '{run_id}' wrote no {path.name}")
    return read_csv(path)


@extractor("surface_taps", "group", "taps", "length", "windward", "exclude_pole_stations")
def surface_taps(ctx, spec, run_id):
    """Surface Cp at pressure taps (x / L, azimuth phi from the windward meridian) on
    a body of revolution along x whose flow is symmetric about the windward plane: at
    each tap, a least-squares plane in (x, r phi) through the two nearest wall faces of
    each quadrant around it (faces mirrored across the symmetry plane, so that taps on
    it are surrounded too) — second order on a smooth surface grid, and never an
    extrapolation along a direction the grid is coarse in. The taps of the
    `exclude_pole_stations` stations nearest each pole are left out. Returns a Curve
    over the taps' row numbers (the reference side uses x = "#row")."""
    from .extract import _need  # extract imports this module to register it
    t = run_surface(ctx, spec, run_id)
    length = float(spec.get("length", 1.0))
    wind = np.asarray(spec.get("windward", [0.0, 0.0, 1.0]), dtype=float)
    wind /= np.linalg.norm(wind)
    side = np.cross([1.0, 0.0, 0.0], wind)
    phi = np.arctan2(np.abs(t["y"] * side[1] + t["z"] * side[2]), t["y"] * wind[1] + t["z"] * wind[2])
    radius = np.hypot(t["y"], t["z"]) / length
    # the symmetric extension: phi, -phi and 2 pi - phi
    fx = np.tile(t["x"] / length, 3)
    fphi = np.concatenate([phi, -phi, 2.0 * np.pi - phi])
    fr = np.tile(radius, 3)
    cp = np.tile(t["cp"], 3)
    tx, tphi = _tap_rows(ctx, _need(spec, "taps", "the tap table"))
    stations = np.unique(tx)
    skip = int(spec.get("exclude_pole_stations", 2))
    excluded = set(stations[:skip]) | set(stations[len(stations) - skip:]) if skip > 0 else set()
    order = np.argsort(t["x"])
    keep, values = [], []
    for i, (x0, p0) in enumerate(zip(tx, np.radians(tphi))):
        if x0 in excluded:
            continue
        r0 = float(np.interp(x0 * length, t["x"][order], radius[order] * length)) / length
        dx = fx - x0
        ds = 0.5 * (fr + r0) * (fphi - p0)  # arc length about the axis, in units of L
        d2 = dx * dx + ds * ds
        chosen = []
        for qx in (dx >= 0.0, dx < 0.0):
            for qs in (ds >= 0.0, ds < 0.0):
                quadrant = np.nonzero(qx & qs)[0]
                if quadrant.size < 2:
                    raise HarnessError(f"surface_taps: too few faces around the tap x/L = {x0}, phi = {np.degrees(p0):g}")
                chosen.extend(quadrant[np.argsort(d2[quadrant])[:2]])
        near = np.array(chosen)
        a = np.column_stack([np.ones(near.size), dx[near], ds[near]])
        coef, *_ = np.linalg.lstsq(a, cp[near], rcond=None)
        keep.append(i)
        values.append(coef[0])
    if not keep:
        raise HarnessError("surface_taps: every tap was excluded")
    return Curve(np.array(keep, dtype=float), np.array(values), "Cp at the taps")


@extractor("body_loads", "group", "quantity", "angle_of_attack", "absolute")
def body_loads(ctx, spec, run_id):
    """A load coefficient of run.json's forces.<group>: the body axes of NUMERICS §0.1
    (X, Y, Z, K, M, N: forward, starboard, down; the nose at -x of the grid), or the
    wind axes of the pitch plane at the run's angle of attack: drag along the free
    stream, lift normal to it (positive up, against z). `absolute`: the magnitude."""
    import json
    import math
    with open(ctx.run_dir(run_id) / "run.json") as f:
        forces = json.load(f)["forces"]
    group = spec.get("group", "body")
    if group not in forces:
        raise HarnessError(f"run.json of '{run_id}' has no force group '{group}' (groups: {', '.join(forces)})")
    b = forces[group]["body_axes"]
    q = spec.get("quantity", "drag")
    if q in b:
        value = b[q]
    elif q in ("drag", "lift"):
        a = math.radians(float(ctx.resolve(run_id, spec.get("angle_of_attack", "input:flow.angle_of_attack"))))
        # free stream in body axes: (-cos a, 0, -sin a) (the body moves at (cos a, 0, sin a))
        value = -(b["X"] * math.cos(a) + b["Z"] * math.sin(a)) if q == "drag" else b["X"] * math.sin(a) - b["Z"] * math.cos(a)
    else:
        raise HarnessError(f"body_loads: quantity must be one of X, Y, Z, K, M, N, drag, lift; got {q!r}")
    return abs(value) if spec.get("absolute", False) else value


def meridians(t):
    """The wall faces of a surface table grouped into meridians: (azimuth from +z in
    degrees, face indices sorted by x) per meridian, by azimuth. A grid station's x varies
    with the azimuth (the meridians start at the pole squares' edges), so faces of one x
    are not a ring; a meridian's faces are those whose azimuths lie within 0.05 degrees of
    the next (their centres' azimuths differ by round-off). Groups with fewer than half
    the faces of the longest (the pole squares' faces, whose azimuths scatter) are left
    out."""
    phi = np.degrees(np.arctan2(-t["y"], t["z"]))
    order = np.argsort(phi)
    groups = np.split(order, np.flatnonzero(np.diff(phi[order]) > 0.05) + 1)
    longest = max(g.size for g in groups)
    return [(float(np.mean(phi[g])), g[np.argsort(t["x"][g])]) for g in groups if g.size >= longest // 2]


def around(t, column, station, lines=None):
    """(azimuth from +z in degrees, the column) at x = station around the body: along each
    meridian (`lines`: meridians(t), passed when the caller already has them) the column
    interpolated linearly in x; meridians that do not reach the station are left out."""
    out = []
    for phi, g in (meridians(t) if lines is None else lines):
        x = t["x"][g]
        if x[0] <= station <= x[-1]:
            out.append((phi, float(np.interp(station, x, t[column][g]))))
    return np.array([a for a, _ in out]), np.array([v for _, v in out])


def azimuthal_mean(t, column, x):
    """The column's mean around the body at each x of `x` (grid units): the trapezoidal
    rule over the azimuth, periodic, of around()'s values. Where the meridians reaching a
    station leave a gap wider than four times their median spacing (the station beyond
    some meridians' ends) the mean is NaN rather than a mean of one side."""
    lines = meridians(t)
    mean = np.full(len(x), np.nan)
    for i, station in enumerate(x):
        phi, v = around(t, column, station, lines)
        if phi.size < 3:
            continue
        gaps = np.diff(np.append(phi, phi[0] + 360.0))
        if gaps.max() > 4.0 * np.median(gaps):
            continue
        mean[i] = np.sum(0.5 * (v + np.roll(v, -1)) * gaps) / 360.0
    return mean


def meridian_stations(t, lines=None):
    """The x of the longest meridian's faces: stations as fine as the grid, for a curve
    of azimuthal means along the body (`lines`: meridians(t), when the caller has them)."""
    return t["x"][max((g for _, g in (meridians(t) if lines is None else lines)), key=len)]


def with_crossflow_friction(t):
    """The surface table with two columns more: r, the face centre's distance from the
    axis, and cf_phi, the skin friction's component along the azimuth phi (from +z,
    phi = atan2(-y, z)): cf . e_phi with e_phi = (0, -cos phi, -sin phi), positive where
    the wall flow turns from windward (phi = 0) towards leeward on the phi > 0 side."""
    if not all(c in t for c in ("cf_x", "cf_y", "cf_z")):
        raise HarnessError("the surface table has no skin friction (cf_x, cf_y, cf_z)")
    phi = np.arctan2(-t["y"], t["z"])
    return dict(t, r=np.hypot(t["y"], t["z"]), cf_phi=-t["cf_y"] * np.cos(phi) - t["cf_z"] * np.sin(phi))


def separation_azimuth(t, station, lines=None):
    """Where the cross flow separates at x = station: the azimuth from the windward line
    at which the circumferential skin friction first vanishes going leeward (linear
    between meridians), the mean of the two sides; NaN where neither side's changes sign.
    `t`: with_crossflow_friction's table. The zero of the circumferential friction is
    the usual marker of the primary cross-flow separation line of a body at incidence
    (where skin-friction lines converge it is nearly parallel to the axis)."""
    phi, tau = around(t, "cf_phi", station, lines)
    sides = []
    for sign in (1.0, -1.0):  # phi > 0 side: flow to leeward has tau > 0; phi < 0 side: tau < 0
        half = sign * phi >= 0.0
        a, s = sign * phi[half], sign * tau[half]
        order = np.argsort(a)
        a, s = a[order], s[order]
        crossing = np.flatnonzero((s[:-1] > 0.0) & (s[1:] <= 0.0))
        if crossing.size:
            n = crossing[0]
            sides.append(a[n] + (a[n + 1] - a[n]) * s[n] / (s[n] - s[n + 1]))
    return float(np.mean(sides)) if sides else float("nan")


@extractor("separation_azimuth", "group", "station", "length")
def separation_azimuth_at(ctx, spec, run_id):
    """The cross-flow separation line's azimuth from the windward line, in degrees, at
    x / L = station (separation_azimuth)."""
    from .extract import _need  # extract imports this module to register it
    station = float(_need(spec, "station", "the axial station x / L"))
    value = separation_azimuth(with_crossflow_friction(run_surface(ctx, spec, run_id)), station * float(spec.get("length", 1.0)))
    if not np.isfinite(value):
        raise HarnessError(f"run '{run_id}': the circumferential skin friction changes sign nowhere at x / L = {station}")
    return value


@extractor("axial_profile", "group", "y", "length", "stations")
def axial_profile(ctx, spec, run_id):
    """A surface column (cp, cf_signed, ...) against x / L: its mean around the body
    (azimuthal_mean: along each meridian interpolated to the station, then averaged over
    the azimuth) at the x / L of `stations`, a table under reference_data/ ({file, where,
    x}) — the points its reference is given at. Stations beyond the meridians' end faces
    (a tap on a pole) are left out."""
    from .extract import _need  # extract imports this module to register it
    t = run_surface(ctx, spec, run_id)
    column = _need(spec, "y", "the surface column")
    if column not in t:
        raise HarnessError(f"surface_{spec.get('group', 'body')}.csv of run '{run_id}' has no column '{column}'")
    length = float(spec.get("length", 1.0))
    st = _need(spec, "stations", "the table of stations {file, where, x}")
    if not isinstance(st, dict) or "file" not in st or "x" not in st:
        raise HarnessError("axial_profile: 'stations' needs {file, x} and optionally where")
    ref = ReferenceFile(ctx.reference_root, st["file"])
    x0 = ref.column(st["x"], ref.rows_where(st["where"]) if "where" in st else None)
    # A tap at a pole (x = 0, the stagnation point) lies beyond the meridians' first face
    # centres: left out, and said so in the curve's name, rather than extrapolated.
    mean = azimuthal_mean(t, column, x0 * length)
    inside = np.isfinite(mean)
    if not inside.any():
        raise HarnessError(f"axial_profile: no station of {st['file']} lies where the meridians reach all around the body")
    dropped = int((~inside).sum())
    name = f"{column}(x/L)" + (f", {dropped} station(s) beyond the end faces left out" if dropped else "")
    return Curve(x0[inside], mean[inside], name)


@extractor("force_part", "group", "part", "component")
def force_part(ctx, spec, run_id):
    """One coefficient of run.json's forces.<group>: its `part` (pressure or friction,
    or total) and `component` (cfx ... cmz, in grid axes)."""
    import json
    with open(ctx.run_dir(run_id) / "run.json") as f:
        forces = json.load(f)["forces"]
    group = spec.get("group", "body")
    if group not in forces:
        raise HarnessError(f"run.json of '{run_id}' has no force group '{group}' (groups: {', '.join(forces)})")
    part = spec.get("part", "total")
    if part not in ("total", "pressure", "friction"):
        raise HarnessError(f"force_part: part must be total, pressure or friction; got {part!r}")
    table = forces[group] if part == "total" else forces[group][part]
    component = spec.get("component", "cfx")
    if component not in ("cfx", "cfy", "cfz", "cmx", "cmy", "cmz"):
        raise HarnessError(f"force_part: component must be one of cfx ... cmz; got {component!r}")
    return float(table[component])
