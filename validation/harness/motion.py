"""Extractors of dual-time runs on moving grids: steps.csv (one row per physical step) and
motion.csv (a free body's path). Registered in schema.EXTRACT like the others."""
import math

import numpy as np

from .errors import HarnessError
from .schema import extractor

TRANSLATIONS = ("x", "y", "z")


def run_table(ctx, run_id, name):
    """A dual-time run's per-step table `name` (steps.csv, motion.csv), refused when empty."""
    from .extract import read_csv  # the one CSV reader (extract imports this module)
    t = read_csv(ctx.run_dir(run_id) / name)
    if t["time"].size == 0:
        raise HarnessError(f"{name} of '{run_id}' has no rows")
    return t


def _steps(ctx, run_id):
    return run_table(ctx, run_id, "steps.csv")


def last_periods(t, omega, periods, whose):
    """The rows of times t within the last `periods` periods 2 pi / omega; refused unless the
    run covers one period more (the start-up transient's) and 8 steps a period."""
    window = t >= t[-1] - periods * 2.0 * math.pi / omega - 1e-12 * t[-1]
    # 1e-9: a step written to 14 digits ends a whole number of periods a rounding short.
    covered = t[-1] * omega / (2.0 * math.pi)
    if covered < (periods + 1.0) * (1.0 - 1e-9) or np.count_nonzero(window) < 8 * periods:
        raise HarnessError(f"{whose} covers {covered:.2f} periods in {t.size} steps; the fit needs {periods:g} "
                           "after the first, 8 steps or more each")
    return window


def _translation(ctx, run_id):
    """The one translational [[motion.oscillation]] of a run: (axis, amplitude, w, phase rad)."""
    motion = ctx.inputs[run_id].get("motion", {})
    found = [o for o in motion.get("oscillation", []) if o.get("dof") in TRANSLATIONS]
    if motion.get("type") != "prescribed" or len(found) != 1 or len(motion["oscillation"]) != 1:
        raise HarnessError(f"oscillation_force: run '{run_id}' needs [motion] type = \"prescribed\" with exactly "
                           "one [[motion.oscillation]], a translation (dof x, y or z)")
    o = found[0]
    return o["dof"], float(o["amplitude"]), float(o["angular_frequency"]), math.radians(float(o.get("phase", 0.0)))


@extractor("oscillation_force", "part", "periods", "group", "radius")
def oscillation_force(ctx, spec, run_id):
    """The force on a sphere in prescribed translational oscillation, split into the part in
    phase with its velocity (part = "drag": A / (6 pi mu R)) and the part in phase with its
    acceleration (part = "mass": B / (rho V / 2)), where the force on the body is
    -(A u + B du/dt) + const, fitted by least squares over the last `periods` periods of
    steps.csv. Flow units: rho = 1, mu = 1 / Re; the force is the coefficient times
    1/2 A_ref (output.reference_area)."""
    part = spec.get("part")
    if part not in ("drag", "mass"):
        raise HarnessError(f"oscillation_force: part must be \"drag\" or \"mass\", got {part!r}")
    axis, amplitude, omega, phase = _translation(ctx, run_id)
    periods = float(spec.get("periods", 2))
    group = spec.get("group", "body")
    radius = float(spec.get("radius", 0.5))
    steps = _steps(ctx, run_id)
    column = f"{group}_cf{axis}"
    if column not in steps:
        raise HarnessError(f"steps.csv of '{run_id}' has no column '{column}' (columns: {', '.join(steps)})")
    t = steps["time"]
    window = last_periods(t, omega, periods, f"oscillation_force: run '{run_id}'")
    # Displacement amplitude sin(w t + phase): velocity and acceleration.
    u = amplitude * omega * np.cos(omega * t[window] + phase)
    du = -amplitude * omega ** 2 * np.sin(omega * t[window] + phase)
    area = float(ctx.input_value(run_id, "output.reference_area"))
    force = steps[column][window] * 0.5 * area
    design = np.column_stack([u, du, np.ones_like(u)])
    (a, b, _), *_ = np.linalg.lstsq(design, force, rcond=None)
    reynolds = float(ctx.input_value(run_id, "flow.reynolds"))
    if part == "drag":
        return float(-a / (6.0 * math.pi * radius / reynolds))
    return float(-b / (0.5 * 4.0 / 3.0 * math.pi * radius ** 3))


def _motion(ctx, run_id):
    return run_table(ctx, run_id, "motion.csv")


def earth_velocity(m):
    """The body origin's velocity in earth axes, R(e) (u, v, w) (NUMERICS §11.3), per row."""
    e0, e1, e2, e3 = (m[k] for k in ("e0", "e1", "e2", "e3"))
    u, v, w = m["u"], m["v"], m["w"]
    return np.column_stack([
        (1 - 2 * (e2 * e2 + e3 * e3)) * u + 2 * (e1 * e2 - e0 * e3) * v + 2 * (e1 * e3 + e0 * e2) * w,
        2 * (e1 * e2 + e0 * e3) * u + (1 - 2 * (e1 * e1 + e3 * e3)) * v + 2 * (e2 * e3 - e0 * e1) * w,
        2 * (e1 * e3 - e0 * e2) * u + 2 * (e2 * e3 + e0 * e1) * v + (1 - 2 * (e1 * e1 + e2 * e2)) * w,
    ])


def gravity_direction(gravity, whose):
    """(unit vector, magnitude) of a gravity vector in earth axes: the grid's axes (the body
    starts turned 180 degrees about z from them, x_B = -x, y_B = -y, z_B = z:
    motion/grid_axes.hpp). `whose` names it in the error."""
    g = np.array([float(v) for v in gravity])
    size = float(np.linalg.norm(g))
    if g.shape != (3,):
        raise HarnessError(f"{whose}: [motion] gravity must be a vector of 3, got {list(gravity)}")
    if size == 0.0:
        raise HarnessError(f"{whose}: [motion] gravity is zero")
    return g / size, size


def fall_components(m, down):
    """Per row of motion.csv: the body's velocity against gravity (negative when falling,
    as Uhlmann & Dusek quote it) and the size of its part across gravity."""
    v = earth_velocity(m)
    along = v @ down
    return -along, np.linalg.norm(v - np.outer(along, down), axis=1)


def _gravity(ctx, run_id):
    motion = ctx.inputs[run_id].get("motion", {})
    if motion.get("type") != "free" or "gravity" not in motion:
        raise HarnessError(f"run '{run_id}' needs [motion] type = \"free\" with a gravity vector")
    return gravity_direction(motion["gravity"], f"run '{run_id}'")


@extractor("fall_velocity", "part", "window")
def fall_velocity(ctx, spec, run_id):
    """A falling body's velocity over the last `window` time units of motion.csv, averaged:
    part = "vertical" (against gravity: negative when falling, as Uhlmann & Dusek quote it),
    "horizontal" (its magnitude) or "angle" (of the path from the vertical, degrees)."""
    part = spec.get("part")
    if part not in ("vertical", "horizontal", "angle"):
        raise HarnessError(f"fall_velocity: part must be vertical, horizontal or angle, got {part!r}")
    m = _motion(ctx, run_id)
    down, _ = _gravity(ctx, run_id)
    window = float(spec.get("window", 5.0))
    last = m["time"] >= m["time"][-1] - window
    if m["time"][-1] < 2.0 * window:
        raise HarnessError(f"fall_velocity: run '{run_id}' ends at t = {m['time'][-1]:g}, before twice the window {window:g}")
    vertical, horizontal = (float(np.mean(c[last])) for c in fall_components(m, down))
    if part == "vertical":
        return vertical
    if part == "horizontal":
        return horizontal
    return math.degrees(math.atan2(horizontal, -vertical))


@extractor("release_acceleration", "steps")
def release_acceleration(ctx, spec, run_id):
    """A body released from rest: its acceleration along gravity at t = 0+, over g. The fall
    velocity over its first `steps` steps is fitted as a0 t - c t^(3/2) (the viscous history
    force grows as sqrt(t) from release, Basset), and a0 / g returned."""
    m = _motion(ctx, run_id)
    down, g = _gravity(ctx, run_id)
    n = int(spec.get("steps", 8))
    if m["time"].size < n or n < 3:
        raise HarnessError(f"release_acceleration: run '{run_id}' has {m['time'].size} steps; the fit needs "
                           f"`steps` ({n}) of them, 3 or more")
    t = m["time"][:n]
    fall = earth_velocity(m)[:n] @ down
    (a0, _), *_ = np.linalg.lstsq(np.column_stack([t, t ** 1.5]), fall, rcond=None)
    return float(a0 / g)


def body_axis(m):
    """Per row of motion.csv: the body's x axis in earth axes, R(e) x_B."""
    e0, e1, e2, e3 = (m[k] for k in ("e0", "e1", "e2", "e3"))
    return np.column_stack([1 - 2 * (e2 * e2 + e3 * e3), 2 * (e1 * e2 + e0 * e3), 2 * (e1 * e3 - e0 * e2)])


def axis_from_vertical_deg(m, down):
    """Per row of motion.csv: the angle (degrees, 0 to 90) between the body's x axis,
    R(e) x_B in earth axes, and the unit vector `down`."""
    return np.degrees(np.arccos(np.minimum(1.0, np.abs(body_axis(m) @ down))))


@extractor("axis_from_vertical", "at")
def axis_from_vertical(ctx, spec, run_id):
    """The angle (degrees, 0 to 90) between a free body's x axis and gravity: at the end of
    the run (at = "end"), at release ("start") or the largest it reached ("max"). A slender
    body released near vertical turns broadside, towards 90 (the Munk moment)."""
    m = _motion(ctx, run_id)
    down, _ = _gravity(ctx, run_id)
    angles = axis_from_vertical_deg(m, down)
    at = spec.get("at", "end")
    if at not in ("end", "start", "max"):
        raise HarnessError(f"axis_from_vertical: at must be end, start or max, got {at!r}")
    return float({"end": angles[-1], "start": angles[0], "max": np.max(angles)}[at])


@extractor("motion_extreme", "column", "reduce", "from_time")
def motion_extreme(ctx, spec, run_id):
    """The largest (reduce = "max") or smallest ("min") value of a motion.csv column from
    `from_time` on: e.g. coupling_change, how far the body's velocities were from agreeing
    with the flow's loads when each step ended."""
    m = _motion(ctx, run_id)
    column = spec.get("column", "")
    if column not in m:
        raise HarnessError(f"motion.csv of '{run_id}' has no column {column!r} (columns: {', '.join(m)})")
    reduce = spec.get("reduce", "max")
    if reduce not in ("max", "min"):
        raise HarnessError(f"motion_extreme: reduce must be max or min, got {reduce!r}")
    values = m[column][m["time"] >= float(spec.get("from_time", 0.0))]
    if values.size == 0:
        raise HarnessError(f"motion_extreme: run '{run_id}' has no step from t = {spec.get('from_time', 0.0)}")
    return float(np.max(values) if reduce == "max" else np.min(values))


@extractor("speed_rise", "from_time")
def speed_rise(ctx, spec, run_id):
    """The largest rise of a free body's speed |(u, v, w)| over one step from `from_time` on,
    relative to the speed: at most 0 for a body that only decelerates (a coasting body
    under its drag; an added-mass instability makes it oscillate)."""
    m = _motion(ctx, run_id)
    speed = np.sqrt(m["u"] ** 2 + m["v"] ** 2 + m["w"] ** 2)[m["time"] >= float(spec.get("from_time", 0.0))]
    if speed.size < 2:
        raise HarnessError(f"speed_rise: run '{run_id}' has fewer than two steps from t = {spec.get('from_time', 0.0)}")
    return float(np.max(np.diff(speed) / speed[1:]))


def free_body_frame(run_input, whose):
    """What a free body's path through the water is measured in, from its run's input:
    (origin at release, the water's velocity far from it (water_velocity), gravity's unit
    vector), grid axes."""
    motion = run_input.get("motion", {})
    if motion.get("type") != "free" or "gravity" not in motion:
        raise HarnessError(f"{whose} needs [motion] type = \"free\" with a gravity vector")
    down, _ = gravity_direction(motion["gravity"], whose)
    origin = np.array([float(v) for v in motion.get("origin", [0.0, 0.0, 0.0])])
    if origin.shape != (3,):
        raise HarnessError(f"{whose}: motion.origin must be a vector of 3")
    return origin, water_velocity(run_input, whose), down


def water_velocity(run_input, whose):
    """The water's velocity far from the body, grid axes, from a run's input:
    bc.farfield.velocity, or without it the unit stream +x, which a flow angle of attack
    or drift would turn: those runs must give it."""
    far = run_input.get("bc", {}).get("farfield", {})
    flow = run_input.get("flow", {})
    if "velocity" in far:
        stream = np.array([float(v) for v in far["velocity"]])
    elif float(flow.get("angle_of_attack", 0.0)) != 0.0 or float(flow.get("drift_angle", 0.0)) != 0.0:
        raise HarnessError(f"{whose}: with a flow angle the water's velocity is not +x: give bc.farfield.velocity")
    else:
        stream = np.array([1.0, 0.0, 0.0])
    if stream.shape != (3,):
        raise HarnessError(f"{whose}: bc.farfield.velocity must be a vector of 3")
    return stream


def water_path(m, frame):
    """Per row of motion.csv, a free body's displacement through the water since release,
    P = x_O(t) - x_O(0) - V_w t (grid axes), and its two readings in the vertical plane:
    travel (P along the horizontal direction the body heads into the stream, -V_w's) and
    rise (P against gravity)."""
    origin, stream, down = frame
    p = np.column_stack([m["x"], m["y"], m["z"]]) - origin - np.outer(m["time"], stream)
    ahead = -(stream - (stream @ down) * down)
    if np.linalg.norm(ahead) == 0.0:
        raise HarnessError("the water's velocity is along gravity: no horizontal travel to measure the path by")
    ahead /= np.linalg.norm(ahead)
    return p, p @ ahead, -(p @ down)


def _path(ctx, run_id):
    return water_path(_motion(ctx, run_id), free_body_frame(ctx.inputs[run_id], f"run '{run_id}'"))


@extractor("path", "part", "reduce")
def path(ctx, spec, run_id):
    """A free body's path through the water in the vertical plane, in L: part = "rise"
    (against gravity since release) or "travel" (horizontally, against the stream), its
    largest (reduce = "max"), smallest ("min") or last ("end") value."""
    part, reduce = spec.get("part"), spec.get("reduce", "end")
    if part not in ("rise", "travel"):
        raise HarnessError(f"path: part must be rise or travel, got {part!r}")
    if reduce not in ("max", "min", "end"):
        raise HarnessError(f"path: reduce must be max, min or end, got {reduce!r}")
    _, travel, rise = _path(ctx, run_id)
    values = rise if part == "rise" else travel
    return float({"max": np.max(values), "min": np.min(values), "end": values[-1]}[reduce])


@extractor("path_difference", "other")
def path_difference(ctx, spec, run_id):
    """How far apart two runs' paths through the water are (the same manoeuvre at two time
    steps or on two grids): the largest distance |P_run(t) - P_other(t)| over the times of
    `run` up to the shorter run's end, `other`'s path interpolated linearly to them (both
    paths start at P = 0 at t = 0), in L."""
    other = spec.get("other", "")
    if not other:
        raise HarnessError("path_difference: give `other`, the run to compare the path with")
    m_a, m_b = _motion(ctx, run_id), _motion(ctx, other)
    p_a, _, _ = _path(ctx, run_id)
    p_b, _, _ = _path(ctx, other)
    t_b = np.concatenate([[0.0], m_b["time"]])
    p_b = np.vstack([np.zeros(3), p_b])
    within = m_a["time"] <= t_b[-1] + 1e-12
    if not np.any(within):
        raise HarnessError(f"path_difference: '{other}' ends before '{run_id}''s first step")
    t = m_a["time"][within]
    at = np.column_stack([np.interp(t, t_b, p_b[:, k]) for k in range(3)])
    return float(np.max(np.linalg.norm(p_a[within] - at, axis=1)))


def _horizontal_path(ctx, run_id):
    """(time, ahead, starboard, yaw in degrees) of a free body's path through the water in
    the horizontal plane: ahead along the direction it heads into the stream at release,
    starboard across it (down x ahead: marine axes)."""
    m = _motion(ctx, run_id)
    frame = free_body_frame(ctx.inputs[run_id], f"run '{run_id}'")
    p, travel, _ = water_path(m, frame)
    _, stream, down = frame
    ahead = -(stream - (stream @ down) * down)
    ahead /= np.linalg.norm(ahead)
    return m["time"], travel, p @ np.cross(down, ahead), m["yaw_deg"]


def _first_crossing(t, values, level):
    """The first time |values| reaches level (interpolated), or None."""
    a = np.abs(values)
    at = np.nonzero(a >= level)[0]
    if at.size == 0:
        return None
    k = int(at[0])
    if k == 0:
        return float(t[0])
    return float(np.interp(level, [a[k - 1], a[k]], [t[k - 1], t[k]]))


@extractor("turning_circle", "part", "window")
def turning_circle(ctx, spec, run_id):
    """A turning circle's figures from a free body's path through the water (ITTC): part =
    "advance" (distance ahead when the heading has turned 90 degrees), "transfer" (sideways
    then), "tactical_diameter" (sideways when it has turned 180 degrees), all in L and
    positive, or "turn_rate" (the heading's rate over the last `window` time units,
    degrees per L/U, its size)."""
    part = spec.get("part")
    t, ahead, starboard, yaw = _horizontal_path(ctx, run_id)
    if part == "turn_rate":
        window = float(spec.get("window", 1.0))
        last = t >= t[-1] - window
        if np.count_nonzero(last) < 3:
            raise HarnessError(f"turning_circle: run '{run_id}' has fewer than 3 steps in its last {window:g}")
        slope = np.polyfit(t[last], np.unwrap(np.radians(yaw[last])), 1)[0]
        return float(abs(math.degrees(slope)))
    if part not in ("advance", "transfer", "tactical_diameter"):
        raise HarnessError(f"turning_circle: part must be advance, transfer, tactical_diameter or turn_rate, got {part!r}")
    heading = np.degrees(np.unwrap(np.radians(yaw)))
    level = 180.0 if part == "tactical_diameter" else 90.0
    when = _first_crossing(t, heading, level)
    if when is None:
        raise HarnessError(f"turning_circle: run '{run_id}' turned {np.max(np.abs(heading)):.1f} degrees, "
                           f"not the {level:g} its {part} needs")
    return float(abs(np.interp(when, t, ahead if part == "advance" else starboard)))


@extractor("zigzag_overshoot", "column", "switch_at", "which")
def zigzag_overshoot(ctx, spec, run_id):
    """A zig-zag's overshoot angle (ITTC): how far the attitude (column yaw_deg or
    pitch_deg of motion.csv, degrees from release) went past `switch_at` after the
    surface's `which`-th reversal, i.e. its `which`-th extreme beyond the switching angle
    (an extreme of the attitude whose size exceeds switch_at), less switch_at."""
    m = _motion(ctx, run_id)
    column = spec.get("column")
    if column not in ("yaw_deg", "pitch_deg"):
        raise HarnessError(f"zigzag_overshoot: column must be yaw_deg or pitch_deg, got {column!r}")
    switch = float(_need_number(spec, "switch_at", "the switching angle, degrees"))
    which = int(spec.get("which", 1))
    a = m[column]
    rising = np.diff(a)
    # An extreme: the attitude's rate changes sign (a plateau counts once, at its start).
    turns = [k for k in range(1, a.size - 1) if rising[k - 1] * rising[k] < 0.0 or (rising[k - 1] != 0.0 and rising[k] == 0.0)]
    beyond = [a[k] for k in turns if abs(a[k]) > switch]
    if len(beyond) < which:
        raise HarnessError(f"zigzag_overshoot: run '{run_id}' has {len(beyond)} extreme(s) of {column} beyond "
                           f"{switch:g} degrees; the overshoot after reversal {which} needs {which}")
    return float(abs(beyond[which - 1]) - switch)


def _need_number(spec, key, what):
    if key not in spec:
        raise HarnessError(f"give `{key}`: {what}")
    return spec[key]
