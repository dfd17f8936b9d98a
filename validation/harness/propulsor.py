"""Extractors of a body-force propulsor's run in a uniform stream (issue 19 bar 1):
the momentum and angular momentum its disk gives the water, measured as the change of
their fluxes between two planes across the stream, and the slipstream's far-wake velocity
against actuator-disk momentum theory. Registered in schema.EXTRACT like the others.

The planes are index planes of box grids whose i direction runs along x, the propulsor's
axis (±x); the flow is in the solver's units (rho = 1, free stream U along +x, total head
1/2 U^2 + p_inf with p_inf = 0).
"""
import json
import math
from pathlib import Path

import numpy as np

from .errors import HarnessError
from .schema import extractor


def _propulsor(ctx, run_id):
    with open(ctx.run_dir(run_id) / "run.json") as f:
        data = json.load(f)
    if "propulsor" not in data:
        raise HarnessError(f"run.json of '{run_id}' has no propulsor (its case needs a [propulsor] table)")
    return data["propulsor"]


def _disk(ctx, run_id):
    """(centre, hub radius, tip radius, thickness) from the run's input."""
    centre = np.array([float(v) for v in ctx.input_value(run_id, "propulsor.centre")])
    axis = [float(v) for v in ctx.inputs[run_id].get("propulsor", {}).get("axis", [-1.0, 0.0, 0.0])]
    if abs(abs(axis[0]) - math.hypot(*axis)) > 1e-12:
        raise HarnessError(f"run '{run_id}': the propulsor extractors need an axis along x, got {axis}")
    tip = 0.5 * float(ctx.input_value(run_id, "propulsor.diameter"))
    hub = tip * float(ctx.input_value(run_id, "propulsor.hub_ratio"))
    return centre, hub, tip, float(ctx.input_value(run_id, "propulsor.thickness"))


def plane(zones, x):
    """The cells of every zone's i plane whose centres lie nearest x (box zones with i along
    x): a dict of flat arrays: y, z (centres), area, p, u, v, w."""
    parts = []
    for z in zones:
        xs = z.centres[0, 0, :, 0]
        if not np.allclose(z.centres[..., 0], xs[None, None, :], atol=1e-9 * (1.0 + np.ptp(xs))):
            raise HarnessError(f"zone '{z.name}': a plane extractor needs box zones whose i direction runs along x")
        if x < z.x[0, 0, 0, 0] or x > z.x[0, 0, -1, 0]:
            continue
        i = int(np.argmin(np.abs(xs - x)))
        dy = np.diff(z.x[0, :, i, 1])
        dz = np.diff(z.x[:, 0, i, 2])
        parts.append({"y": z.centres[:, :, i, 1].ravel(), "z": z.centres[:, :, i, 2].ravel(),
                      "area": np.outer(dz, dy).ravel(),
                      **{k: z.fields[k][:, :, i].ravel() for k in ("p", "u", "v", "w")}})
    if not parts:
        raise HarnessError(f"no zone of the solution reaches x = {x}")
    return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}


def axial_flux(cells, free_stream=1.0):
    """The x momentum the plane carries beyond the free stream's: sum of (u (u - U) + p) dA."""
    return float(np.sum((cells["u"] * (cells["u"] - free_stream) + cells["p"]) * cells["area"]))


def angular_flux(cells, centre):
    """The angular momentum about the x axis through `centre` the plane carries: sum of
    u (y w - z v) dA (positive right-handed about +x)."""
    y, z = cells["y"] - centre[1], cells["z"] - centre[2]
    return float(np.sum(cells["u"] * (y * cells["w"] - z * cells["v"]) * cells["area"]))


def _solution(ctx, run_id):
    return ctx.solution(run_id)


@extractor("propulsor_momentum_balance", "quantity", "x_upstream", "x_downstream")
def momentum_balance(ctx, spec, run_id):
    """|Delta flux / load - 1|: the change between the planes of the x momentum flux with the
    pressure (quantity = "thrust": against T, the water pushed along +x) or of the angular
    momentum flux about the axis (quantity = "torque": against Q, the water swirled with
    the blades) — the control-volume balance of NUMERICS §12.4 item 7."""
    quantity = spec.get("quantity")
    if quantity not in ("thrust", "torque"):
        raise HarnessError(f"extractor 'propulsor_momentum_balance': 'quantity' must be thrust or torque, got {quantity!r}")
    prop = _propulsor(ctx, run_id)
    zones = _solution(ctx, run_id)
    up, down = plane(zones, float(spec.get("x_upstream"))), plane(zones, float(spec.get("x_downstream")))
    if quantity == "thrust":
        gained, load = axial_flux(down) - axial_flux(up), float(prop["thrust"])
    else:
        centre = _disk(ctx, run_id)[0]
        # The water turns with the blades, about the spin axis w_p = +-e_a (right- or
        # left-handed about the thrust's direction), e_a along +-x.
        axis = ctx.inputs[run_id].get("propulsor", {}).get("axis", [-1.0, 0.0, 0.0])
        spin_along_x = math.copysign(1.0, float(axis[0])) * (1.0 if prop["rotation"] == "right" else -1.0)
        gained = spin_along_x * (angular_flux(down, centre) - angular_flux(up, centre))
        load = float(prop["torque"])
    return abs(gained / load - 1.0)


@extractor("slipstream_peak", "x")
def slipstream_peak(ctx, spec, run_id):
    """|du_computed / du_theory - 1| for the slipstream's largest axial velocity increment at
    the plane x, against the actuator disk's (momentum theory, no swirl): along the stream
    tube through the disk's most loaded radius the total head rises by the pressure jump
    dp = f_a Delta (Hough-Ordway's peak, r* = 2/3), so there u = sqrt(2 (1/2 U^2 + dp - p))
    with p the pressure the computation has at that point (the box's far wake is not at
    exactly the free stream's pressure)."""
    prop = _propulsor(ctx, run_id)
    if prop.get("swirl", True):
        raise HarnessError(f"run '{run_id}': slipstream_peak compares with momentum theory without swirl "
                           "(propulsor.swirl = false)")
    _, hub, tip, thickness = _disk(ctx, run_id)
    thrust = float(prop["thrust"])
    a_x = 105.0 / 8.0 * thrust / (math.pi * thickness * (3.0 * hub + 4.0 * tip) * (tip - hub))  # NUMERICS §9.3
    jump = a_x * thickness * 2.0 / (3.0 * math.sqrt(3.0))
    cells = plane(_solution(ctx, run_id), float(spec.get("x")))
    k = int(np.argmax(cells["u"]))
    theory = math.sqrt(2.0 * (0.5 + jump - cells["p"][k]))
    return abs((cells["u"][k] - 1.0) / (theory - 1.0) - 1.0)


@extractor("propulsor_value", "field")
def propulsor_value(ctx, spec, run_id):
    """A number of run.json's propulsor report: "wake_fraction", "advance_ratio", "thrust",
    "rps"..., or the rpm controller's "rpm_control.surplus" (|T - R| / R when it last measured)."""
    node = _propulsor(ctx, run_id)
    field = spec.get("field")
    for part in str(field).split("."):
        if not isinstance(node, dict) or part not in node:
            raise HarnessError(f"run.json of '{run_id}': the propulsor report has no '{field}'")
        node = node[part]
    return abs(float(node)) if field == "rpm_control.surplus" else float(node)


@extractor("thrust_deduction", "towed")
def thrust_deduction(ctx, spec, run_id):
    """t = (T - R_towed) / T: the self-propelled run's thrust against the resistance the same
    vehicle had towed without its propulsor (run `towed`, the same grid and settings), both
    along the thrust axis from the walls' force coefficients (C_F = 2 F / A_ref)."""
    thrust = float(_propulsor(ctx, run_id)["thrust"])
    towed = spec.get("towed")
    axis = np.array([float(v) for v in ctx.inputs[run_id].get("propulsor", {}).get("axis", [-1.0, 0.0, 0.0])])
    axis /= np.linalg.norm(axis)
    with open(ctx.run_dir(towed) / "run.json") as f:
        forces = json.load(f)["forces"]
    area = float(ctx.input_value(towed, "output.reference_area"))
    along = sum(np.dot([forces[g]["cfx"], forces[g]["cfy"], forces[g]["cfz"]], axis) for g in forces)
    return (thrust - (-0.5 * area * along)) / thrust


def propulsor_per_step(run_dir):
    """propulsor.csv of a dual-time run at the end of each physical step: narwhal writes a row
    after every sub-iteration, steps.csv how many sub-iterations each step took. Returns the
    columns with steps.csv's `time` in place of `iteration`."""
    from .extract import read_csv  # the one CSV reader (extract imports this module)
    run_dir = Path(run_dir)
    rows, steps = read_csv(run_dir / "propulsor.csv"), read_csv(run_dir / "steps.csv")
    counts = np.asarray(steps["subiterations"], dtype=int)
    n = len(rows["iteration"])
    if counts.sum() != n or np.any(counts < 1):
        raise HarnessError(f"{run_dir}: propulsor.csv has {n} rows, but steps.csv's sub-iterations add up to "
                           f"{counts.sum()}: expected one row per sub-iteration of this run")
    last = np.cumsum(counts) - 1
    out = {k: np.asarray(v)[last] for k, v in rows.items() if k != "iteration"}
    out["time"] = np.asarray(steps["time"])
    return out
