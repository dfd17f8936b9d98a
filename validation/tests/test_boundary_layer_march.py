"""The independent boundary-layer solver behind the Baldwin-Lomax code-to-code reference
is itself checked against the Blasius solution before its turbulent answer is trusted."""
import math
import sys
import unittest

from support import ROOT
from harness.reference import ReferenceFile

sys.path.insert(0, str(ROOT / "validation" / "tools"))
import boundary_layer_march as bl  # noqa: E402


class LaminarMarching(unittest.TestCase):
    def test_blasius_skin_friction_and_shape_factor(self):
        blasius = ReferenceFile(ROOT / "reference_data", "flat_plate/blasius_laminar_flat_plate.csv")
        fpp0 = float(blasius.column("fpp")[0])
        reynolds = 1e5
        rows = bl.march(reynolds, ny=160, nx=400, x_start=1e-3, x_end=1.0, first=2e-5, top=0.06, model="laminar")
        x, cf, h = rows[-1, 0], rows[-1, 2], rows[-1, 3]
        # Cf sqrt(Re_x) = 2 f''(0); the start profile is forgotten by x = 1000 x_start
        self.assertAlmostEqual(cf * math.sqrt(reynolds * x) / (2.0 * fpp0), 1.0, delta=5e-3)
        self.assertAlmostEqual(h, 2.59, delta=0.02)  # Blasius delta*/theta = 1.7208/0.6641

    def test_baldwin_lomax_eddy_viscosity_is_zero_at_the_wall_and_positive_inside(self):
        import numpy as np
        y = bl.wall_normal_grid(200, 1e-6, 0.05)
        u = np.minimum((y / 0.02) ** (1.0 / 7.0), 1.0)
        nut = bl.baldwin_lomax(y, u, 1.0 / 5e6)
        self.assertEqual(nut[0], 0.0)
        self.assertTrue((nut[1:] > 0.0).all())


if __name__ == "__main__":
    unittest.main()
