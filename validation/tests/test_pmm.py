"""pmm_derivative (harness/pmm.py): the derivatives a force history was built of come back
from pure sway, pure yaw and pure pitch runs; what a motion does not vary is refused."""
import math
import tempfile
import unittest
from pathlib import Path

import support  # noqa: F401
import numpy as np

from harness.errors import HarnessError
from harness.extract import EXTRACT
from test_motion_extractors import Ctx, write_csv

OMEGA = 1.5  # omega L / U
STEPS_PER_PERIOD = 64


def run_input(oscillations):
    return {"grid": {"length": 1.0}, "bc": {"farfield": {"velocity": [1.0, 0.0, 0.0]}},
            "output": {"reference_area": 1.0, "reference_length": 1.0, "moment_centre": [0.4, 0.0, 0.0]},
            "motion": {"type": "prescribed", "pivot": [0.4, 0.0, 0.0],
                       "oscillation": [{"dof": d, "amplitude": a, "angular_frequency": OMEGA, "phase": p}
                                       for d, a, p in oscillations]}}


def write_steps(directory, t, force_body, moment_body, axes):
    """steps.csv of group 'hull' with forces given in body axes; `axes` (n, 3, 3): the body's
    x, y, z unit vectors in grid axes at each step."""
    force = np.einsum("nki,nk->ni", axes, force_body)
    moment = np.einsum("nki,nk->ni", axes, moment_body)
    write_csv(Path(directory) / "run" / "steps.csv",
              ["step", "time", "hull_cfx", "hull_cfy", "hull_cfz", "hull_cmx", "hull_cmy", "hull_cmz"],
              [(n + 1, t[n], *force[n], *moment[n]) for n in range(t.size)])


def times(periods=3):
    return np.arange(1, periods * STEPS_PER_PERIOD + 1) * (2 * math.pi / OMEGA / STEPS_PER_PERIOD)


def fit(directory, inputs, name):
    return EXTRACT["pmm_derivative"][0](Ctx(directory, {"run": inputs}), {"derivative": name, "groups": ["hull"]}, "run")


class HorizontalPlane(unittest.TestCase):
    # Y' and N' built of these (with constants, and Y'v v, N'v v in the yaw run's tiny v).
    Y = {"v": -0.03, "r": 0.008, "vdot": -0.016, "rdot": -0.0004}
    N = {"v": -0.01, "r": -0.005, "vdot": 0.0002, "rdot": -0.0009}

    def build(self, d, sway, yaw_amplitude):
        """Sway y = sway sin(w t) and yaw psi = -yaw_amplitude cos(w t) (radians) about z:
        body axes x_B = (-cos psi, -sin psi, 0), y_B = (sin psi, -cos psi, 0), z_B = z."""
        t = times()
        psi = -yaw_amplitude * np.cos(OMEGA * t)
        psi_dot = yaw_amplitude * OMEGA * np.sin(OMEGA * t)
        psi_ddot = yaw_amplitude * OMEGA ** 2 * np.cos(OMEGA * t)
        y_dot = sway * OMEGA * np.cos(OMEGA * t)
        y_ddot = -sway * OMEGA ** 2 * np.sin(OMEGA * t)
        axes = np.array([[[-math.cos(p), -math.sin(p), 0.0], [math.sin(p), -math.cos(p), 0.0], [0.0, 0.0, 1.0]]
                         for p in psi])
        # The body through the water (grid axes (-1, y_dot, 0)) in body axes, and its rate.
        v = -np.sin(psi) - y_dot * np.cos(psi)
        v_dot = -np.cos(psi) * psi_dot - y_ddot * np.cos(psi) + y_dot * np.sin(psi) * psi_dot
        state = {"v": v, "r": psi_dot, "vdot": v_dot, "rdot": psi_ddot}
        side = 0.001 + sum(c * state[k] for k, c in self.Y.items())
        turn = -0.0002 + sum(c * state[k] for k, c in self.N.items())
        zero = np.zeros_like(t)
        write_steps(d, t, np.column_stack([zero + 0.004, side, zero]), np.column_stack([zero, zero, turn]), axes)
        return run_input([("y", sway, 0.0), ("yaw", math.degrees(yaw_amplitude), -90.0)] if yaw_amplitude
                         else [("y", sway, 0.0)])

    def test_pure_yaw_gives_the_rotary_derivatives(self):
        # Heading along the path: psi_0 = a w / U, so v = -(psi_0 cos w t)^3 / 3 and is not
        # fitted (pmm.py): C'v v then passes for C'rdot rdot, by |C'v| psi_0^2 / (3 w^2) at
        # most, and the r derivatives err by O(psi_0^2) relative.
        psi_0 = 0.05 * OMEGA
        with tempfile.TemporaryDirectory() as d:
            inputs = self.build(d, 0.05, psi_0)
            for name, expected, c_v in (("Yr", self.Y["r"], 0.0), ("Yrdot", self.Y["rdot"], self.Y["v"]),
                                        ("Nr", self.N["r"], 0.0), ("Nrdot", self.N["rdot"], self.N["v"])):
                delta = 2 * psi_0 ** 2 * abs(expected) + abs(c_v) * psi_0 ** 2 / (3 * OMEGA ** 2)
                self.assertAlmostEqual(fit(d, inputs, name), expected, delta=delta, msg=name)
            with self.assertRaisesRegex(HarnessError, "does not vary v"):
                fit(d, inputs, "Yv")

    def test_pure_sway_gives_the_velocity_and_acceleration_derivatives(self):
        with tempfile.TemporaryDirectory() as d:
            inputs = self.build(d, 0.05, 0.0)
            for name, expected in (("Yv", self.Y["v"]), ("Yvdot", self.Y["vdot"]),
                                   ("Nv", self.N["v"]), ("Nvdot", self.N["vdot"])):
                self.assertAlmostEqual(fit(d, inputs, name), expected, delta=1e-9, msg=name)
            with self.assertRaisesRegex(HarnessError, "does not vary r"):
                fit(d, inputs, "Nr")


class VerticalPlane(unittest.TestCase):
    def test_pure_pitch_gives_the_vertical_rotary_derivatives(self):
        # Pitch theta about the grid's y: y_B = -y, so q = -theta_dot; through the water at
        # (-1, 0, z_dot), w = -sin(theta) + z_dot cos(theta): heave z = a sin(w t) with
        # theta = a w cos(w t) keeps w = 0 to O(theta_0^3).
        Z = {"q": -0.007, "qdot": -0.0003}
        M = {"q": -0.003, "qdot": -0.0008}
        a = 0.04
        t = times()
        theta = a * OMEGA * np.cos(OMEGA * t)
        theta_dot = -a * OMEGA ** 2 * np.sin(OMEGA * t)
        q, q_dot = -theta_dot, a * OMEGA ** 3 * np.cos(OMEGA * t)
        # R_y(theta) e_x = (cos, 0, -sin); body x_B = -R e_x, y_B = -R e_y = -e_y, z_B = R e_z = (sin, 0, cos).
        axes = np.array([[[-math.cos(h), 0.0, math.sin(h)], [0.0, -1.0, 0.0], [math.sin(h), 0.0, math.cos(h)]]
                         for h in theta])
        heave = 0.0005 + Z["q"] * q + Z["qdot"] * q_dot
        pitch = 0.0001 + M["q"] * q + M["qdot"] * q_dot
        zero = np.zeros_like(t)
        with tempfile.TemporaryDirectory() as d:
            write_steps(d, t, np.column_stack([zero, zero, heave]), np.column_stack([zero, pitch, zero]), axes)
            inputs = run_input([("z", a, 0.0), ("pitch", math.degrees(a * OMEGA), 90.0)])
            for name, expected in (("Zq", Z["q"]), ("Zqdot", Z["qdot"]), ("Mq", M["q"]), ("Mqdot", M["qdot"])):
                self.assertAlmostEqual(fit(d, inputs, name), expected, delta=2 * (a * OMEGA) ** 2 * abs(expected),
                                       msg=name)
            # The pitch the other way round: w = 2 a w cos(w t), in phase with q'dot, so the
            # two cannot be told apart in a measured force.
            with self.assertRaisesRegex(HarnessError, "cannot be told apart"):
                fit(d, run_input([("z", a, 0.0), ("pitch", math.degrees(a * OMEGA), -90.0)]), "Zq")


class Refusals(unittest.TestCase):
    def test_names_motions_and_short_runs_are_checked(self):
        with tempfile.TemporaryDirectory() as d:
            inputs = HorizontalPlane().build(d, 0.05, 0.0)
            with self.assertRaisesRegex(HarnessError, "derivative must be"):
                fit(d, inputs, "Xu")
            with self.assertRaisesRegex(HarnessError, "fitted against"):
                fit(d, inputs, "Yq")
            two = run_input([("yaw", 3.0, 0.0), ("pitch", 2.0, 0.0)])
            with self.assertRaisesRegex(HarnessError, "one rotating"):
                fit(d, two, "Yr")
            with self.assertRaisesRegex(HarnessError, "periods"):
                EXTRACT["pmm_derivative"][0](Ctx(d, {"run": inputs}),
                                             {"derivative": "Yv", "groups": ["hull"], "periods": 3}, "run")
            # A flow angle without the far field's velocity: the water is not known to be +x.
            turned = dict(inputs, bc={}, flow={"drift_angle": 4.0})
            with self.assertRaisesRegex(HarnessError, "give bc.farfield.velocity"):
                fit(d, turned, "Yv")


if __name__ == "__main__":
    unittest.main()
