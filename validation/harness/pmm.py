"""Extractors of planar-motion-mechanism runs: a captive vehicle in prescribed oscillation
([motion] type = "prescribed", moving grid) whose forces give the velocity, rotary and
acceleration derivatives of a manoeuvring model (solver/manoeuvring/manoeuvring_model.hpp).

Pure sway (a y oscillation) gives Y'v, N'v, Y'vdot, N'vdot; pure yaw (y and yaw together,
the heading along the path, so that v = 0) gives Y'r, N'r, Y'rdot, N'rdot; heave and pitch
likewise give the Z' and M' derivatives in w and q. The body's motion through the water is
rebuilt from the case's oscillations (motion/prescribed_motion.hpp) at each step's time; the
forces of steps.csv (grid axes, the moment about output.moment_centre, which moves with the
body) are turned into body axes (x forward, y starboard, z down: the grid turned 180 degrees
about z, motion/grid_axes.hpp) and the component fitted by least squares,
    C = C_0 + sum_k C_k x_k,
over the last `periods` periods, where x_k are those of v', r', v'dot, r'dot (or w', q',
w'dot, q'dot) that the motion varies: primes with the water's speed U and the length L
(v' = v / U, r' = r L / U, v'dot = vdot L / U^2, r'dot = rdot L^2 / U^2). The coefficients
are F / (1/2 rho U^2 L^2) and M / (1/2 rho U^2 L^3): the runs set output.reference_area = L^2
and output.reference_length = L (checked).
"""
import math

import numpy as np

from .captive import _groups, _input_number
from .errors import HarnessError
from .motion import last_periods, run_table, water_velocity
from .schema import extractor

DOFS = ("x", "y", "z", "roll", "pitch", "yaw")
# A component's plane of motion: the velocity and the angular velocity it is fitted against.
PLANES = {"Y": "vr", "N": "vr", "Z": "wq", "M": "wq"}
# A variable the motion varies by less than this part of its partner's range is not fitted:
# a pure yaw's v is O(psi_0^3) of U, not zero (a sinusoidal heading follows a sinusoidal
# path only to that order), and in phase with r'dot; left out, C'v v passes for part of
# C'rdot r'dot (by |C'v| psi_0^2 / (3 w'^2) at most) and C'r errs by O(psi_0^2) relative:
# pure yaw runs keep psi_0 small and take Y'v, N'v from a drift sweep or a pure sway run.
NEGLIGIBLE = 1e-2
# The largest condition number of the fit's columns (scaled to unit length) accepted.
MAX_CONDITION = 100.0


def _derivative_name(name):
    """'Yr' -> ('Y', 'r'); 'Nvdot' -> ('N', 'vdot')."""
    if not isinstance(name, str) or len(name) < 2 or name[0] not in PLANES:
        raise HarnessError(f"pmm_derivative: derivative must be one of Y, N, Z, M followed by a variable "
                           f"(v, r, vdot, rdot; w, q, wdot, qdot), got {name!r}")
    component, variable = name[0], name[1:]
    plane = PLANES[component]
    if variable not in (plane[0], plane[1], plane[0] + "dot", plane[1] + "dot"):
        raise HarnessError(f"pmm_derivative: {component}' is fitted against {plane[0]}, {plane[1]} and their "
                           f"rates, got {name!r}")
    return component, variable


class PrescribedPath:
    """The body's motion of a prescribed run: translation of the pivot and one rotation at
    most (a planar mechanism turns the model about one axis), as motion/prescribed_motion.hpp
    composes them."""

    def __init__(self, motion, whose):
        if motion.get("type") != "prescribed":
            raise HarnessError(f"{whose}: pmm_derivative needs [motion] type = \"prescribed\"")
        self.pivot = np.array([float(v) for v in motion.get("pivot", [0.0, 0.0, 0.0])])
        self.velocity = np.array([float(v) for v in motion.get("velocity", [0.0, 0.0, 0.0])])
        self.terms = []
        for o in motion.get("oscillation", []):
            if o.get("dof") not in DOFS:
                raise HarnessError(f"{whose}: an oscillation's dof must be one of {', '.join(DOFS)}")
            k = DOFS.index(o["dof"])
            amplitude = float(o["amplitude"]) * (math.pi / 180.0 if k >= 3 else 1.0)
            self.terms.append((k, amplitude, float(o["angular_frequency"]), math.radians(float(o.get("phase", 0.0)))))
        rotations = {k for k, *_ in self.terms if k >= 3}
        if len(rotations) > 1:
            raise HarnessError(f"{whose}: pmm_derivative takes one rotating degree of freedom, the motion has "
                               f"{', '.join(DOFS[k] for k in sorted(rotations))}")
        self.rotation_axis = (np.eye(3)[min(rotations) - 3] if rotations else np.zeros(3))
        if not self.terms:
            raise HarnessError(f"{whose}: pmm_derivative needs [[motion.oscillation]] entries")
        self.frequencies = {w for _, _, w, _ in self.terms}

    def coordinates(self, t, order=0):
        """The six coordinates (x, y, z, roll, pitch, yaw) at times t, or their `order`-th rates."""
        c = np.zeros((t.size, 6))
        if order == 0:
            c[:, :3] = np.outer(t, self.velocity)
        elif order == 1:
            c[:, :3] = self.velocity
        for k, a, w, phase in self.terms:
            c[:, k] += a * w ** order * np.sin(w * t + phase + order * math.pi / 2.0)
        return c

    def angle(self, t, order=0):
        return self.coordinates(t, order)[:, 3:] @ self.rotation_axis if self.rotation_axis.any() else np.zeros(t.size)

    def rotation(self, angle):
        """R for each angle about the one rotation axis (Rodrigues)."""
        k = self.rotation_axis
        kx = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
        return np.array([np.eye(3) + math.sin(a) * kx + (1.0 - math.cos(a)) * kx @ kx for a in angle])


def body_motion(path, t, centre, water):
    """Body-axes (u, v, w) of the moment centre through the water, (p, q, r), and the time
    rates of those body-axes components, per time; and the turn D R^T from grid to body axes.
    With R' = [omega]x R, the rates are D R^T (a_pivot + alpha x arm - omega x (V_pivot - W))
    and D R^T alpha (arm = R (centre - pivot), all in grid axes)."""
    angle = path.angle(t)
    rot = path.rotation(angle)
    omega = np.outer(path.angle(t, 1), path.rotation_axis)  # grid axes
    alpha = np.outer(path.angle(t, 2), path.rotation_axis)
    pivot_velocity = path.coordinates(t, 1)[:, :3]
    pivot_acceleration = path.coordinates(t, 2)[:, :3]
    arm = np.einsum("nij,j->ni", rot, centre - path.pivot)
    through_water = pivot_velocity + np.cross(omega, arm) - water
    rate = pivot_acceleration + np.cross(alpha, arm) - np.cross(omega, pivot_velocity - water)
    flip = np.diag([-1.0, -1.0, 1.0])  # body axes at rest: the grid's turned 180 degrees about z
    to_body = np.einsum("ij,nkj->nik", flip, rot)  # D R^T
    in_body = lambda vectors: np.einsum("nij,nj->ni", to_body, vectors)  # noqa: E731
    return in_body(through_water), in_body(omega), in_body(rate), in_body(alpha), to_body


@extractor("pmm_derivative", "derivative", "groups", "length", "periods")
def pmm_derivative(ctx, spec, run_id):
    """One derivative (`derivative`: Yv, Yr, Yvdot, Yrdot, N..., Zw, Zq, Zwdot, Zqdot,
    M...) of the wall groups `groups` from a prescribed-motion run, fitted over its last
    `periods` periods (default 1; the run must cover one more). A derivative whose variable
    the motion does not vary is an error: a pure yaw run has no Y'v."""
    component, variable = _derivative_name(spec.get("derivative"))
    groups = _groups(spec)
    run_input = ctx.inputs[run_id]
    whose = f"run '{run_id}'"
    path = PrescribedPath(run_input.get("motion", {}), whose)
    if len(path.frequencies) != 1:
        raise HarnessError(f"{whose}: pmm_derivative needs one frequency for all oscillations, got {sorted(path.frequencies)}")
    omega = path.frequencies.pop()
    length = float(spec.get("length", _input_number(ctx, run_id, "grid.length", 1.0)))
    area = _input_number(ctx, run_id, "output.reference_area", 1.0)
    arm = _input_number(ctx, run_id, "output.reference_length", 1.0)
    if not (math.isclose(area, length ** 2, rel_tol=1e-6) and math.isclose(arm, length, rel_tol=1e-6)):
        raise HarnessError(f"{whose}: PMM derivatives need output.reference_area = L^2 and output.reference_length = L "
                           f"(L = {length}); got {area} and {arm}")
    water = water_velocity(run_input, whose)
    speed = float(np.linalg.norm(water - path.velocity))
    if speed == 0.0:
        raise HarnessError(f"{whose}: the body does not move through the water (no speed to make derivatives by)")
    centre = np.array([float(v) for v in run_input.get("output", {}).get("moment_centre", [0.0, 0.0, 0.0])])

    steps = run_table(ctx, run_id, "steps.csv")
    t = steps["time"]
    window = last_periods(t, omega, float(spec.get("periods", 1)), f"pmm_derivative: {whose}")
    tw = t[window]
    # The force in grid axes, then in body axes.
    force = np.zeros((tw.size, 3))
    moment = np.zeros((tw.size, 3))
    for g in groups:
        for k, axis in enumerate("xyz"):
            for target, kind in ((force, "cf"), (moment, "cm")):
                column = f"{g}_{kind}{axis}"
                if column not in steps:
                    raise HarnessError(f"steps.csv of '{run_id}' has no column '{column}'")
                target[:, k] += steps[column][window]
    linear, angular, linear_rate, angular_rate, to_body = body_motion(path, tw, centre, water)
    force_b = np.einsum("nij,nj->ni", to_body, force)
    moment_b = np.einsum("nij,nj->ni", to_body, moment)
    value = {"Y": force_b[:, 1], "Z": force_b[:, 2], "M": moment_b[:, 1], "N": moment_b[:, 2]}[component]
    plane = PLANES[component]
    index = {"v": (linear, linear_rate, 1), "w": (linear, linear_rate, 2),
             "q": (angular, angular_rate, 1), "r": (angular, angular_rate, 2)}
    columns = {}
    for name in plane:
        now, rate, k = index[name]
        rate_scale = length / speed if name in "qr" else 1.0
        columns[name] = now[:, k] / speed * rate_scale
        columns[name + "dot"] = rate[:, k] * length / speed ** 2 * rate_scale
    # Only the variables the motion varies, against their partner of the same order.
    partner = {plane[0]: plane[1], plane[1]: plane[0]}
    partner.update({a + "dot": b + "dot" for a, b in list(partner.items())})
    varied = {n: c for n, c in columns.items() if np.ptp(c) > NEGLIGIBLE * np.ptp(columns[partner[n]])}
    if variable not in varied:
        raise HarnessError(f"pmm_derivative: {whose}'s motion does not vary {variable} (it varies "
                           f"{', '.join(varied)}): {component}{variable} cannot be fitted from it")
    names = list(varied)
    design = np.column_stack([np.ones(tw.size)] + [varied[n] for n in names])
    # A velocity in phase with an acceleration (a heave with the pitch turned the wrong way:
    # w with q'dot) leaves the fit to the measurement's noise: refused.
    scaled = design / np.linalg.norm(design, axis=0)
    if np.linalg.cond(scaled) > MAX_CONDITION:
        raise HarnessError(f"pmm_derivative: {whose}'s {', '.join(names)} cannot be told apart (in phase with each "
                           "other): a planar-motion run varies a velocity (pure sway, heave) or a rotation with the "
                           "heading along the path (pure yaw, pitch)")
    solution, *_ = np.linalg.lstsq(design, value, rcond=None)
    return float(solution[1 + names.index(variable)])
