"""Means over whole periods of a swinging force history (harness/periodic.py): exact for a
periodic swing whatever the window, the spread of the periods' means, and a history that
does not swing."""
import math
import unittest

import numpy as np

import support  # noqa: F401

from harness.errors import HarnessError
from harness.periodic import interval_mean, period_average, rises


class PeriodAverages(unittest.TestCase):
    def test_a_periodic_swing_s_mean_is_exact_where_the_window_s_is_biased(self):
        # 8.3 periods of 1.3 after the transient: the window holds a part period.
        period, amplitude = 1.3, 0.2
        t = np.arange(1, 601) * 0.02
        s = 1.0 + amplitude * np.sin(2 * math.pi * t / period + 0.4) + 0.05 * np.sin(4 * math.pi * t / period)
        other = 3.0 + 0.01 * np.cos(2 * math.pi * t / period)
        average = period_average(t, np.column_stack([s, other]), discard=1.0)
        self.assertEqual(average.reference, 0, "the column that swings most bounds the periods")
        self.assertGreaterEqual(average.periods, 6)
        self.assertAlmostEqual(average.end - average.start, average.periods * period, delta=1e-3)
        self.assertLess(abs(average.means[0] - 1.0), 1e-4 * amplitude)
        self.assertLess(abs(average.means[1] - 3.0), 1e-5)
        keep = t >= t[0] + 1.0
        window_mean = interval_mean(t[keep], s[keep], t[keep][0], t[keep][-1])
        self.assertGreater(abs(window_mean - 1.0), 1e-3 * amplitude, "the plain window mean is biased")
        self.assertLess(average.standard_error([1.0, 0.0]), 1e-4 * amplitude, "a periodic swing's periods agree")

    def test_of_the_columns_that_swing_strongly_the_one_with_the_most_periods_bounds_them(self):
        # A slow swing (period 4) slightly stronger than a fast one (period 1): the fast one's
        # rises bound the periods, so that most of the window is averaged over; a weak
        # ripple (period 0.25) is not a candidate.
        t = np.linspace(0.0, 12.0, 12001)
        slow = 0.11 * np.sin(2 * math.pi * t / 4.0)
        fast = 0.10 * np.sin(2 * math.pi * t)
        ripple = 0.01 * np.sin(2 * math.pi * t / 0.25)
        average = period_average(t, np.column_stack([slow, fast, ripple]), discard=0.0)
        self.assertEqual((average.reference, average.periods), (1, 10))  # rises at t = 1 ... 11

    def test_the_standard_error_is_that_of_the_periods_means(self):
        # A swing whose mean drifts linearly by d per period: periods' means m0 + k d, k = 0
        # ... P - 1, whose standard deviation is d sqrt(P (P + 1) / 12).
        period, d = 1.0, 1e-3
        t = np.linspace(0.0, 10.0, 20001)
        s = 2.0 + 0.3 * np.sin(2 * math.pi * t / period) + d * t / period
        average = period_average(t, s[:, None], discard=0.5)
        p = average.periods
        self.assertEqual(p, 9)
        self.assertAlmostEqual(average.standard_error([1.0]), d * math.sqrt((p + 1) / 12), delta=0.01 * d)
        self.assertEqual(average.standard_error([-1.0]), average.standard_error([1.0]))

    def test_without_two_periods_the_window_s_mean_and_range_stand(self):
        t = np.arange(1, 101) * 0.1
        s = 1.0 + 1e-3 * t  # settling, not swinging
        average = period_average(t, s[:, None], discard=2.0)
        self.assertEqual(average.periods, 0)
        self.assertAlmostEqual(average.means[0], 1.0 + 1e-3 * 0.5 * (2.1 + 10.0), places=12)
        self.assertAlmostEqual(average.standard_error([1.0]), 0.5e-3 * (10.0 - 2.1), places=12)
        steady = period_average(t, np.ones((100, 1)), discard=0.0)
        self.assertEqual((steady.periods, steady.means[0], steady.standard_error([1.0])), (0, 1.0, 0.0))

    def test_a_ripple_about_the_mean_does_not_start_a_period(self):
        t = np.linspace(0.0, 4.0, 4001)
        s = np.sin(2 * math.pi * t) + 0.1 * np.sin(2 * math.pi * 97 * t)
        # One rise near each of t = 1, 2, 3, 4 (the one at 0 had no fall before it); the
        # ripple's own rises through the mean, counted without the hysteresis, are not.
        self.assertEqual(len(rises(t, s, 0.0, 0.25 * s.std())), 4)
        self.assertGreater(len(rises(t, s, 0.0, 0.0)), 8)

    def test_too_short_a_history_is_refused(self):
        with self.assertRaises(HarnessError) as cm:
            period_average(np.array([0.1, 0.2, 0.3]), np.ones((3, 1)), discard=1.0)
        self.assertIn("fewer than two", str(cm.exception))


if __name__ == "__main__":
    unittest.main()
