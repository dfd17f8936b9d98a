import unittest
from pathlib import Path

import numpy as np

from support import ROOT
from harness import potential_flow


def spheroid_exact_cp():
    """(x/L, Cp) on the 6:1 spheroid at zero incidence, the reference file's exact solution."""
    path = ROOT / "reference_data" / "spheroid" / "prolate_spheroid_6to1_potential_flow_cp.csv"
    rows = [l.split(",") for l in path.read_text().splitlines() if l and not l.startswith("#")]
    head = rows[0]
    ia, ix, iphi, icp = (head.index(k) for k in ("alpha_deg", "x_over_L", "phi_deg", "Cp"))
    pts = sorted({(float(r[ix]), float(r[icp])) for r in rows[1:] if float(r[ia]) == 0.0 and float(r[iphi]) == 0.0})
    return np.array(pts)


class EllipticIntegrals(unittest.TestCase):
    def test_known_values(self):
        k, e = potential_flow.complete_elliptic_integrals(np.array([0.0, 0.5]))
        self.assertAlmostEqual(k[0], np.pi / 2, places=14)
        self.assertAlmostEqual(e[0], np.pi / 2, places=14)
        # K(1/2) = Gamma(1/4)^2 / (4 sqrt(pi)); Legendre's relation gives E(1/2)
        k_half = 1.8540746773013719
        self.assertAlmostEqual(k[1], k_half, places=13)
        self.assertAlmostEqual(e[1], (np.pi / 2 + k_half ** 2) / (2 * k_half), places=13)


class Spheroid(unittest.TestCase):
    def test_converges_to_the_exact_cp_at_first_order(self):
        exact = spheroid_exact_cp()
        inner = exact[(exact[:, 0] >= 0.1) & (exact[:, 0] <= 0.9)]
        radius = lambda x: (0.5 / 6.0) * np.sqrt(np.clip(1.0 - (2.0 * x - 1.0) ** 2, 0.0, None))
        errors = []
        for n in (100, 200, 400):
            xm, _, cp = potential_flow.surface_cp(*potential_flow.cosine_nodes(radius, n))
            errors.append(np.abs(np.interp(inner[:, 0], xm, cp) - inner[:, 1]).max())
        self.assertLess(errors[-1], 5e-4)
        for coarse, fine in zip(errors, errors[1:]):
            self.assertGreater(coarse / fine, 1.7)

    def test_stagnation_point(self):
        radius = lambda x: (0.5 / 6.0) * np.sqrt(np.clip(1.0 - (2.0 * x - 1.0) ** 2, 0.0, None))
        _, _, cp = potential_flow.surface_cp(*potential_flow.cosine_nodes(radius, 400))
        self.assertAlmostEqual(cp.max(), 1.0, delta=2e-3)


class SuboffOffsets(unittest.TestCase):
    """The derived reference of the SUBOFF rung (references.potential_flow_cp): its panels
    are the intervals of the offsets table, so its error is estimated by halving them."""

    def offsets(self):
        from harness.reference import ReferenceFile
        ref = ReferenceFile(ROOT / "reference_data", "suboff/suboff_hull_offsets.csv")
        return ref, ref.column("x_over_LOA"), ref.column("r_over_LOA")

    def test_every_other_offset_moves_the_forebody_cp_by_under_2e_3(self):
        _, x, r = self.offsets()
        taps = np.array([0.035, 0.070, 0.105, 0.181])  # the AFF-1 forebody taps
        fine = np.interp(taps, *potential_flow.surface_cp(x, r)[::2])
        keep = np.unique(np.r_[np.arange(0, x.size, 2), x.size - 1])
        coarse = np.interp(taps, *potential_flow.surface_cp(x[keep], r[keep])[::2])
        self.assertLess(np.abs(fine - coarse).max(), 2e-3)

    def test_the_derived_reference_is_the_panel_solution_on_the_offsets(self):
        from harness.references import DERIVED
        ref, x, r = self.offsets()
        curve = DERIVED["potential_flow_cp"](ref, {})
        xm, _, cp = potential_flow.surface_cp(x, r)
        np.testing.assert_array_equal(curve.x, xm)
        np.testing.assert_array_equal(curve.y, cp)
        self.assertAlmostEqual(curve.y.max(), 1.0, delta=0.02)  # the nose's stagnation point


if __name__ == "__main__":
    unittest.main()
