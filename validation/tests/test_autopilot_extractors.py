"""depth_change and control_extreme (harness/autopilot.py) on histories whose answers are
known in closed form: a depth path with a bump past its command, and control angles."""
import math
import tempfile
import unittest
from pathlib import Path

import support  # noqa: F401
import numpy as np

from harness.errors import HarnessError
from harness.extract import EXTRACT
from test_motion_extractors import Ctx, write_csv

ORIGIN = (0.4621, 0.0, 0.0)


def run_input(command=2.0, limit=15.0):
    inputs = {"motion": {"type": "free", "gravity": [0.0, 0.0, 4.5915], "origin": list(ORIGIN)},
              "autopilot": {"surface_limit": limit}}
    if command is not None:
        inputs["autopilot"]["depth_change"] = command
    return inputs


def write_motion(directory, t, depth):
    """A body held at its x in the grid (so travelling through the stream +x at 1) whose
    origin goes `depth` down (+z, along gravity)."""
    write_csv(Path(directory) / "run" / "motion.csv", ["step", "time", "x", "y", "z"],
              [(n + 1, t[n], ORIGIN[0], 0.0, depth[n]) for n in range(t.size)])


def extract(kind, directory, inputs, **spec):
    return EXTRACT[kind][0](Ctx(directory, {"run": inputs}), spec, "run")


class DepthChange(unittest.TestCase):
    def test_a_ramp_with_a_bump_settles_where_the_bump_ends(self):
        # Down 2 L over 4 L/U, then a bump of 0.2 L at t = 5 (1 L/U either side), then 0.01 L
        # past the command from t = 7: outside a band of 0.051 L until t = 5 + 0.745.
        t = np.arange(1, 1001) * 0.01
        depth = 2.0 * np.minimum(t / 4.0, 1.0) + 0.2 * np.maximum(0.0, 1.0 - np.abs(t - 5.0)) + 0.01 * (t > 7.0)
        with tempfile.TemporaryDirectory() as d:
            write_motion(d, t, depth)
            self.assertAlmostEqual(extract("depth_change", d, run_input(), part="settling_time", band=0.051), 5.75,
                                   places=9)
            self.assertAlmostEqual(extract("depth_change", d, run_input(), part="error", last=2.0), 0.01, places=12)
            self.assertAlmostEqual(extract("depth_change", d, run_input(), part="error", from_time=4.0), 0.2, places=12)
            self.assertAlmostEqual(extract("depth_change", d, run_input(), part="overshoot"), 0.2, places=12)

    def test_an_underdamped_approach_overshoots_by_its_first_extreme(self):
        # depth = 2 (1 - exp(-t/2) cos t): past 2 by 2 exp(-t*/2) |cos t*| at tan t* = -1/2.
        t = np.arange(1, 20001) * 0.001
        with tempfile.TemporaryDirectory() as d:
            write_motion(d, t, 2.0 * (1.0 - np.exp(-t / 2.0) * np.cos(t)))
            peak = math.pi - math.atan(0.5)
            self.assertAlmostEqual(extract("depth_change", d, run_input(), part="overshoot"),
                                   -2.0 * math.exp(-peak / 2.0) * math.cos(peak), places=6)
            # Rising to a command upwards (depth_change < 0), the same path never overshoots it.
            self.assertEqual(extract("depth_change", d, run_input(command=-2.0), part="overshoot"), 0.0)

    def test_refusals_are_named(self):
        t = np.arange(1, 101) * 0.01
        with tempfile.TemporaryDirectory() as d:
            write_motion(d, t, 1.5 * t)
            with self.assertRaisesRegex(HarnessError, "not settled"):
                extract("depth_change", d, run_input(), part="settling_time", band=0.05)
            with self.assertRaisesRegex(HarnessError, "no autopilot.depth_change"):
                extract("depth_change", d, run_input(command=None), part="error")
            with self.assertRaisesRegex(HarnessError, "part must be"):
                extract("depth_change", d, run_input(), part="depth")
            with self.assertRaisesRegex(HarnessError, "needs `band`"):
                extract("depth_change", d, run_input(), part="settling_time")
            with self.assertRaisesRegex(HarnessError, "one of `last` and `from_time`"):
                extract("depth_change", d, run_input(), part="error", last=1.0, from_time=0.5)


class ControlExtreme(unittest.TestCase):
    def test_the_largest_angle_of_any_surface_and_its_part_of_the_limit(self):
        t = np.arange(1, 51) * 0.04
        with tempfile.TemporaryDirectory() as d:
            write_csv(Path(d) / "run" / "controls.csv",
                      ["step", "time", "rudder_deg", "stern_planes_deg", "sail_planes_deg", "pitch_command_deg"],
                      [(n + 1, t[n], 0.0, -14.9 * math.sin(t[n] * math.pi / 4.0), 3.0, -20.0) for n in range(t.size)])
            self.assertAlmostEqual(extract("control_extreme", d, run_input()), 14.9, places=12)
            self.assertAlmostEqual(extract("control_extreme", d, run_input(), relative_to="autopilot.surface_limit"),
                                   14.9 / 15.0, places=12)
            self.assertEqual(extract("control_extreme", d, run_input(), columns=["sail_planes_deg"]), 3.0)
            with self.assertRaisesRegex(HarnessError, "no column"):
                extract("control_extreme", d, run_input(), columns=["elevator_deg"])
            with self.assertRaisesRegex(HarnessError, "positive number"):
                extract("control_extreme", d, run_input(limit=0.0), relative_to="autopilot.surface_limit")


if __name__ == "__main__":
    unittest.main()
