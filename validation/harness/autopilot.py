"""Extractors of manoeuvres flown by the autopilots ([autopilot], control/autopilot.hpp):
how a commanded depth change was reached and held, and how far the control surfaces went.

Depth is the autopilot's: the body origin's displacement along gravity since release (the
water's stream is horizontal, so through the water and through the grid agree), in L.
"""
import numpy as np

from .errors import HarnessError
from .motion import free_body_frame, run_table, water_path
from .schema import extractor

SURFACE_COLUMNS = ("rudder_deg", "stern_planes_deg", "sail_planes_deg")


def _depth_error(ctx, run_id):
    """(time, depth since release less the commanded change, the command) of an autopilot
    depth change."""
    run_input = ctx.inputs[run_id]
    whose = f"run '{run_id}'"
    command = run_input.get("autopilot", {}).get("depth_change")
    if command is None:
        raise HarnessError(f"depth_change: {whose} has no autopilot.depth_change")
    m = run_table(ctx, run_id, "motion.csv")
    _, _, rise = water_path(m, free_body_frame(run_input, whose))
    return m["time"], -rise - float(command), float(command)


def _window(t, spec, whose):
    """The rows of the last `last` time units (or from `from_time` on), refused when empty."""
    if "last" in spec and "from_time" in spec:
        raise HarnessError("depth_change: give one of `last` and `from_time`")
    start = t[-1] - float(spec["last"]) if "last" in spec else float(spec.get("from_time", 0.0))
    rows = t >= start - 1e-9 * max(1.0, abs(t[-1]))
    if not np.any(rows):
        raise HarnessError(f"depth_change: {whose} has no step from t = {start:g}")
    return rows


@extractor("depth_change", "part", "last", "from_time", "band")
def depth_change(ctx, spec, run_id):
    """A commanded depth change (autopilot.depth_change, L) as flown, in L or L/U:
    part = "error": the largest |depth - command| over the run's `last` time units (or
    from `from_time` on); "overshoot": how far the depth went past the command (0 if it
    never did); "settling_time": the time from which |depth - command| stays within `band`
    to the run's end (an error when the run ends outside it)."""
    part = spec.get("part")
    t, error, command = _depth_error(ctx, run_id)
    whose = f"run '{run_id}'"
    if part == "error":
        return float(np.max(np.abs(error[_window(t, spec, whose)])))
    if part == "overshoot":
        beyond = error if command >= 0.0 else -error
        return float(max(0.0, np.max(beyond)))
    if part == "settling_time":
        if "band" not in spec:
            raise HarnessError("depth_change: settling_time needs `band`, the depth error it settles within (L)")
        outside = np.nonzero(np.abs(error) > float(spec["band"]))[0]
        if outside.size and outside[-1] == t.size - 1:
            raise HarnessError(f"depth_change: {whose} ends {abs(error[-1]):.4g} L from its command, outside the "
                               f"band of {float(spec['band']):g} L: not settled")
        return float(t[outside[-1] + 1]) if outside.size else float(t[0])
    raise HarnessError(f"depth_change: part must be error, overshoot or settling_time, got {part!r}")


@extractor("control_extreme", "columns", "relative_to")
def control_extreme(ctx, spec, run_id):
    """The largest |angle| any of `columns` of controls.csv (default: every surface's) took
    in the run, degrees; with `relative_to` (a dotted key of the run's input: the limit the
    case sets, e.g. autopilot.surface_limit), as a fraction of that key's value."""
    columns = spec.get("columns", list(SURFACE_COLUMNS))
    controls = run_table(ctx, run_id, "controls.csv")
    missing = [c for c in columns if c not in controls]
    if missing or not columns:
        raise HarnessError(f"control_extreme: controls.csv of '{run_id}' has no column(s) {missing or columns} "
                           f"(columns: {', '.join(controls)})")
    largest = max(float(np.max(np.abs(controls[c]))) for c in columns)
    key = spec.get("relative_to")
    if key is None:
        return largest
    # The limit must be stated in the case, not left to narwhal's default.
    node = ctx.input_value(run_id, key)
    if not isinstance(node, (int, float)) or isinstance(node, bool) or node <= 0:
        raise HarnessError(f"control_extreme: {key} of run '{run_id}' must be a positive number, got {node!r}")
    return largest / float(node)
