"""The propulsor extractors on hand-made box solutions: the planes' momentum and angular
momentum fluxes against T and Q, and the slipstream's peak against momentum theory."""
import json
import math
import tempfile
import unittest
from pathlib import Path

import numpy as np

from support import rung_in_temp_dir

from harness.errors import HarnessError
from harness.extract import Context, extract
from harness.propulsor import plane, propulsor_per_step
from harness.solution import Zone

RUNG = """
[rung]
title = "t"
tiers = ["quick"]

[[run]]
id = "disk"
input = "in.toml"

[[check]]
name = "c"
extract = { kind = "propulsor_momentum_balance", run = "disk", quantity = "thrust", x_upstream = -1.0, x_downstream = 1.0 }
comparator = "max"
tolerance = 1e-3
rationale = "because"
"""

INPUT = {"propulsor": {"centre": [0.0, 0.0, 0.0], "diameter": 1.0, "hub_ratio": 0.2, "thickness": 0.2,
                       "axis": [-1.0, 0.0, 0.0]}}


def box_zone(n=(8, 20, 20), extent=2.0, downstream=None):
    """A box zone [-2, 2]^3; behind x = 0 the cells take downstream(y, z) -> (p, u, v, w)."""
    xs = np.linspace(-extent, extent, n[0] + 1)
    ys = np.linspace(-extent, extent, n[1] + 1)
    zs = np.linspace(-extent, extent, n[2] + 1)
    Z, Y, X = np.meshgrid(zs, ys, xs, indexing="ij")
    nodes = np.stack([X, Y, Z], axis=-1)
    zone = Zone("box", nodes, {k: np.zeros((n[2], n[1], n[0])) for k in ("p", "u", "v", "w")})
    zone.fields["u"][:] = 1.0
    c = zone.centres
    behind = c[..., 0] > 0.0
    if downstream:
        p, u, v, w = downstream(c[..., 1], c[..., 2])
        for name, value in zip(("p", "u", "v", "w"), (p, u, v, w)):
            zone.fields[name] = np.where(behind, value, zone.fields[name])
    return zone


class PropulsorExtractors(unittest.TestCase):
    def setUp(self):
        self.dir, self.rung = rung_in_temp_dir(RUNG)

    def context(self, zone, propulsor, inputs=INPUT):
        d = self.dir / "runs" / "disk"
        d.mkdir(parents=True, exist_ok=True)
        (d / "run.json").write_text(json.dumps({"propulsor": propulsor}))
        ctx = Context(self.rung, {"disk": d}, {"disk": inputs})
        ctx._solutions["disk"] = [zone]
        return ctx

    def test_the_plane_covers_the_box(self):
        cells = plane([box_zone()], 0.3)
        self.assertAlmostEqual(float(np.sum(cells["area"])), 16.0, places=12)
        with self.assertRaises(HarnessError):
            plane([box_zone()], 5.0)

    def test_a_jet_behind_the_disk_carries_its_thrust(self):
        jet = lambda y, z: (0.0 * y, np.where(y ** 2 + z ** 2 < 0.25, 1.1, 1.0), 0.0 * y, 0.0 * y)  # noqa: E731
        zone = box_zone(downstream=jet)
        cells = plane([zone], 1.0)
        thrust = float(np.sum(cells["u"] * (cells["u"] - 1.0) * cells["area"]))
        spec = {"kind": "propulsor_momentum_balance", "run": "disk", "quantity": "thrust", "x_upstream": -1.0,
                "x_downstream": 1.0}
        self.assertAlmostEqual(extract(self.context(zone, {"thrust": thrust, "torque": 1.0, "rotation": "right"}), spec),
                               0.0, places=12)
        self.assertAlmostEqual(extract(self.context(zone, {"thrust": 2 * thrust, "torque": 1.0, "rotation": "right"}),
                                       spec), 0.5, places=12)

    def test_a_swirl_turned_with_right_handed_blades_about_minus_x_carries_the_torque(self):
        # Right-handed about e_a = -x: the water turns negatively about +x (w = -c y, v = c z).
        c = 0.05
        swirl = lambda y, z: (0.0 * y, 1.0 + 0.0 * y, c * z, -c * y)  # noqa: E731
        zone = box_zone(downstream=swirl)
        cells = plane([zone], 1.0)
        torque = float(np.sum(c * (cells["y"] ** 2 + cells["z"] ** 2) * cells["area"]))
        spec = {"kind": "propulsor_momentum_balance", "run": "disk", "quantity": "torque", "x_upstream": -1.0,
                "x_downstream": 1.0}
        self.assertAlmostEqual(extract(self.context(zone, {"thrust": 1.0, "torque": torque, "rotation": "right"}), spec),
                               0.0, places=12)
        # Left-handed blades would have turned the water the other way: the balance is off by 2.
        self.assertAlmostEqual(extract(self.context(zone, {"thrust": 1.0, "torque": torque, "rotation": "left"}), spec),
                               2.0, places=12)

    def test_the_slipstream_peak_against_momentum_theory(self):
        thrust = 0.075
        tip, hub, thickness = 0.5, 0.1, 0.2
        a_x = 105.0 / 8.0 * thrust / (math.pi * thickness * (3 * hub + 4 * tip) * (tip - hub))
        peak = math.sqrt(1.0 + 2.0 * a_x * thickness * 2.0 / (3.0 * math.sqrt(3.0)))
        found = 1.0 + 0.99 * (peak - 1.0)  # one per cent short of the theory's increment
        slip = lambda y, z: (0.0 * y, np.where(np.hypot(y, z) < 0.4, found, 1.0), 0.0 * y, 0.0 * y)  # noqa: E731
        ctx = self.context(box_zone(downstream=slip), {"thrust": thrust, "torque": 0.01, "swirl": False,
                                                        "rotation": "right"})
        self.assertAlmostEqual(extract(ctx, {"kind": "slipstream_peak", "run": "disk", "x": 1.0}), 0.01, places=10)
        ctx = self.context(box_zone(downstream=slip), {"thrust": thrust, "torque": 0.01, "swirl": True,
                                                        "rotation": "right"})
        with self.assertRaises(HarnessError):
            extract(ctx, {"kind": "slipstream_peak", "run": "disk", "x": 1.0})

    def test_the_propulsor_report_and_the_thrust_deduction(self):
        ctx = self.context(box_zone(), {"thrust": 0.5, "wake_fraction": 0.25, "rpm_control": {"surplus": -1e-3}})
        self.assertEqual(extract(ctx, {"kind": "propulsor_value", "run": "disk", "field": "wake_fraction"}), 0.25)
        self.assertEqual(extract(ctx, {"kind": "propulsor_value", "run": "disk", "field": "rpm_control.surplus"}), 1e-3)
        with self.assertRaises(HarnessError):
            extract(ctx, {"kind": "propulsor_value", "run": "disk", "field": "rpm"})
        # Towed without the propulsor: drag along +x, 0.4 of the thrust's 0.5 (C_F = 2 F / A, A = 2).
        towed = self.dir / "runs" / "towed"
        towed.mkdir(parents=True, exist_ok=True)
        (towed / "run.json").write_text(json.dumps({"forces": {"body": {"cfx": 0.3, "cfy": 0.0, "cfz": 0.0},
                                                              "sail": {"cfx": 0.1, "cfy": 0.05, "cfz": 0.0}}}))
        ctx.run_dirs["towed"] = towed
        ctx.inputs["towed"] = {"output": {"reference_area": 2.0}}
        self.assertAlmostEqual(extract(ctx, {"kind": "thrust_deduction", "run": "disk", "towed": "towed"}), 0.2,
                               places=14)


if __name__ == "__main__":
    unittest.main()


class PropulsorPerStep(unittest.TestCase):
    """propulsor.csv's rows (one per sub-iteration) taken at the end of each physical step."""

    def write(self, rows, subiterations):
        d = Path(tempfile.mkdtemp())
        (d / "propulsor.csv").write_text("iteration,rps,advance_speed,advance_ratio,thrust,torque,resistance\n" +
                                         "".join(f"{300 + i},{10 + i},0.8,0.7,{0.1 * i},0.01,0.2\n"
                                                 for i in range(rows)))
        (d / "steps.csv").write_text("step,time,subiterations\n" +
                                     "".join(f"{n + 1},{0.02 * (n + 1)},{s}\n" for n, s in enumerate(subiterations)))
        return d

    def test_each_steps_last_sub_iteration(self):
        t = propulsor_per_step(self.write(7, [3, 2, 2]))
        np.testing.assert_allclose(t["time"], [0.02, 0.04, 0.06])
        np.testing.assert_allclose(t["rps"], [12, 14, 16])
        np.testing.assert_allclose(t["thrust"], [0.2, 0.4, 0.6])
        self.assertNotIn("iteration", t)

    def test_rows_that_are_not_the_steps_sub_iterations_are_refused(self):
        with self.assertRaisesRegex(HarnessError, "7 rows, but steps.csv's sub-iterations add up to 6"):
            propulsor_per_step(self.write(7, [3, 2, 1]))
