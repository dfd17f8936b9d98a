"""Each comparator on hand-made data, on both sides of its tolerance; GCI on exact data."""
import math
import unittest

import support  # noqa: F401
import numpy as np

from harness.compare import Curve, Family, compare, gci, observed_orders
from harness.errors import HarnessError


class Scalars(unittest.TestCase):
    def test_abs(self):
        self.assertTrue(compare("abs", 1.05, 1.0, 0.06, {})["pass"])
        r = compare("abs", 1.05, 1.0, 0.04, {})
        self.assertFalse(r["pass"])
        self.assertAlmostEqual(r["delta"], 0.05)

    def test_rel(self):
        self.assertTrue(compare("rel", 2.02, 2.0, 0.011, {})["pass"])
        r = compare("rel", 2.02, 2.0, 0.009, {})
        self.assertFalse(r["pass"])
        self.assertAlmostEqual(r["delta"], 0.01)
        with self.assertRaises(HarnessError):
            compare("rel", 1.0, 0.0, 0.1, {})

    def test_scalar_comparator_rejects_a_curve(self):
        with self.assertRaises(HarnessError):
            compare("abs", Curve([0, 1], [0, 1]), 1.0, 0.1, {})

    def test_one_sided_bounds(self):
        self.assertTrue(compare("max", 38.0, None, 40.0, {})["pass"])
        self.assertFalse(compare("max", 41.0, None, 40.0, {})["pass"])
        self.assertTrue(compare("min", 5.5, None, 5.0, {})["pass"])
        r = compare("min", 4.5, None, 5.0, {})
        self.assertFalse(r["pass"])
        self.assertAlmostEqual(r["delta"], -0.5)

    def test_restart_equal(self):
        self.assertTrue(compare("restart_equal", 0.0, None, 0.0, {})["pass"])
        self.assertFalse(compare("restart_equal", 1e-9, None, 1e-12, {})["pass"])


class Profiles(unittest.TestCase):
    def setUp(self):
        self.x = np.linspace(1.0, 2.0, 11)
        self.ref = Curve(np.linspace(0.0, 3.0, 31), 2.0 * np.linspace(0.0, 3.0, 31))

    def test_max_relative(self):
        y = 2.0 * self.x
        y[5] *= 1.03  # one point 3 % off
        r = compare("profile_max", Curve(self.x, y), self.ref, 0.031, {})
        self.assertTrue(r["pass"])
        self.assertAlmostEqual(r["delta"], 0.03)
        self.assertFalse(compare("profile_max", Curve(self.x, y), self.ref, 0.029, {})["pass"])

    def test_rms_relative(self):
        y = 2.0 * self.x * 1.01
        r = compare("profile_rms", Curve(self.x, y), self.ref, 0.0101, {})
        self.assertTrue(r["pass"])
        self.assertAlmostEqual(r["delta"], 0.01)
        self.assertFalse(compare("profile_rms", Curve(self.x, y), self.ref, 0.0099, {})["pass"])

    def test_absolute_mode_and_function_reference(self):
        y = 2.0 * self.x + 0.002
        r = compare("profile_max", Curve(self.x, y), lambda x: 2.0 * x, 0.0021, {"relative": False})
        self.assertTrue(r["pass"])
        self.assertAlmostEqual(r["delta"], 0.002)
        self.assertFalse(compare("profile_max", Curve(self.x, y), lambda x: 2.0 * x, 0.0019, {"relative": False})["pass"])

    def test_points_outside_the_reference_are_an_error(self):
        with self.assertRaises(HarnessError):
            compare("profile_max", Curve([2.5, 3.5], [5.0, 7.0]), self.ref, 0.1, {})

    def test_empty_range_is_an_error(self):
        with self.assertRaises(HarnessError):
            Curve([], [], "cf")


class GridFamilies(unittest.TestCase):
    def test_observed_order_second_order_data(self):
        h = np.array([0.4, 0.2, 0.1, 0.05])
        fam = Family(h, 3.0 * h ** 2)
        self.assertTrue(np.allclose(observed_orders(fam), 2.0))
        self.assertTrue(compare("observed_order", fam, 2.0, 0.1, {"pairs": 2})["pass"])

    def test_observed_order_fails_for_first_order_data(self):
        h = np.array([0.4, 0.2, 0.1])
        r = compare("observed_order", Family(h, 3.0 * h), 2.0, 0.1, {"pairs": 2})
        self.assertFalse(r["pass"])
        self.assertAlmostEqual(r["computed"], 1.0)

    def test_family_order_does_not_depend_on_listing_order(self):
        fam = Family([0.1, 0.4, 0.2], [0.01, 0.16, 0.04])
        self.assertTrue(np.allclose(observed_orders(fam), 2.0))

    def test_family_spread_is_the_largest_departure_from_the_finest(self):
        fam = Family([1.0, 4.0, 2.0], [1.2500, 1.2510, 1.2490])  # finest (h = 1) listed first
        r = compare("family_spread", fam, -1.285, 1e-3, {})
        self.assertAlmostEqual(r["computed"], 0.001 / 1.25)
        self.assertTrue(r["pass"])
        self.assertFalse(compare("family_spread", fam, None, 5e-4, {})["pass"])
        with self.assertRaisesRegex(HarnessError, "family"):
            compare("family_spread", 1.25, None, 1e-3, {})

    def test_gci_on_exact_second_order_data_constant_ratio(self):
        # f = 1 + 0.5 h^2 on h = 4, 2, 1: p = 2, extrapolation exact, and by Roache's
        # definition GCI_fine = 1.25 |(f1 - f2)/f1| / (r^p - 1) = 1.25 * (1.5/1.5) / 3.
        fam = Family([4.0, 2.0, 1.0], [9.0, 3.0, 1.5])
        g, p, fext = gci(fam)
        self.assertAlmostEqual(p, 2.0, places=10)
        self.assertAlmostEqual(fext, 1.0, places=10)
        self.assertAlmostEqual(g, 1.25 * (1.5 / 1.5) / 3.0, places=10)
        self.assertTrue(compare("gci", fam, None, 0.5, {})["pass"])
        self.assertFalse(compare("gci", fam, None, 0.3, {})["pass"])

    def test_gci_non_constant_ratio_recovers_the_order(self):
        h = np.array([3.0, 2.0, 1.0])
        f = 2.0 - 0.1 * h ** 1.5
        g, p, fext = gci(Family(h, f))
        self.assertAlmostEqual(p, 1.5, places=8)
        self.assertAlmostEqual(fext, 2.0, places=8)
        f1, f2 = f[-1], f[-2]
        self.assertAlmostEqual(g, 1.25 * abs((f1 - f2) / f1) / (2.0 ** 1.5 - 1.0), places=8)

    def test_gci_reproduces_the_nparc_worked_example_of_roaches_method(self):
        from support import ROOT
        from harness.reference import ReferenceFile
        ref = ReferenceFile(ROOT / "reference_data", "verification/gci_worked_example_nparc.csv")
        g, p, fext = gci(Family(ref.column("h"), ref.column("value")))
        self.assertAlmostEqual(p, ref.column("p")[0], places=5)
        self.assertAlmostEqual(fext, ref.column("f_exact")[0], places=5)
        self.assertAlmostEqual(g, ref.column("gci_fine")[0], places=6)

    def test_gci_needs_three_grids(self):
        with self.assertRaises(HarnessError):
            gci(Family([2.0, 1.0], [1.0, 1.1]))


if __name__ == "__main__":
    unittest.main()


class ReferenceRows(unittest.TestCase):
    """Tables of several codes: a value is picked by text columns (model, code, grid)."""

    def setUp(self):
        import tempfile
        from pathlib import Path
        self.dir = tempfile.TemporaryDirectory()
        self.root = Path(self.dir.name)
        (self.root / "t.csv").write_text("# provenance: a test table\nmodel,grid,cf\nSA,545x385,0.0027291\n"
                                         "SA,273x193,0.0027285\nSST,545x385,0.0027174\n")

    def tearDown(self):
        self.dir.cleanup()

    def test_value_selected_by_text_columns(self):
        from harness.references import resolve_reference
        v, _ = resolve_reference(None, {"file": "t.csv", "column": "cf", "where": {"model": "SST", "grid": "545x385"}},
                                 self.root)
        self.assertEqual(v, 0.0027174)

    def test_no_match_and_several_matches_are_errors(self):
        from harness.references import resolve_reference
        with self.assertRaisesRegex(HarnessError, "no row where"):
            resolve_reference(None, {"file": "t.csv", "column": "cf", "where": {"model": "kw"}}, self.root)
        with self.assertRaisesRegex(HarnessError, "2 rows match"):
            resolve_reference(None, {"file": "t.csv", "column": "cf", "where": {"model": "SA"}}, self.root)

    def test_minus_subtracts_the_value_of_another_row(self):
        from harness.references import resolve_reference
        v, desc = resolve_reference(None, {"file": "t.csv", "column": "cf", "where": {"model": "SST"},
                                           "minus": {"model": "SA", "grid": "273x193"}}, self.root)
        self.assertAlmostEqual(v, 0.0027174 - 0.0027285, places=15)
        self.assertIn("minus", desc)
        with self.assertRaisesRegex(HarnessError, "2 rows match"):
            resolve_reference(None, {"file": "t.csv", "column": "cf", "where": {"model": "SST"},
                                     "minus": {"model": "SA"}}, self.root)
        with self.assertRaisesRegex(HarnessError, "needs 'where'"):
            resolve_reference(None, {"file": "t.csv", "column": "cf", "minus": {"model": "SST"}}, self.root)

    def test_text_column_is_not_numeric(self):
        from harness.reference import ReferenceFile
        with self.assertRaisesRegex(HarnessError, "not numeric"):
            ReferenceFile(self.root, "t.csv").column("model")


class DuctVortexCells(unittest.TestCase):
    """The vortex-cell count of the duct rung on hand-made stream functions."""

    def grid(self, n=48):
        y = np.linspace(-1.0, 1.0, n)
        return np.meshgrid(y, y)

    def test_eight_cells_of_a_square_duct_pattern(self):
        from harness.duct import count_cells
        y, z = self.grid()
        # sin(4 theta) r^4 = 4 y z (y^2 - z^2): eight lobes of alternating sign, one per
        # half-corner, vanishing on the walls.
        psi = y * z * (y * y - z * z) * (1 - y * y) * (1 - z * z)
        self.assertEqual(count_cells(psi, 0.05 * np.abs(psi).max()), 8)

    def test_one_cell_and_none(self):
        from harness.duct import count_cells
        y, z = self.grid()
        psi = (1 - y * y) * (1 - z * z)
        self.assertEqual(count_cells(psi, 0.05), 1)
        self.assertEqual(count_cells(0.0 * psi, 0.05), 0)

    def test_annotated_result_carries_its_plot_through_min_max(self):
        from harness.duct import Annotated
        r = compare("min", Annotated(8, {"kind": "duct_field"}), None, 8, {})
        self.assertTrue(r["pass"])
        self.assertEqual(r["plot"]["kind"], "duct_field")
        self.assertFalse(compare("max", Annotated(9, {"kind": "duct_field"}), None, 8, {})["pass"])
