"""Statistics of force histories that swing in physical time (a fin stalled on its lee side
sheds): the mean over whole periods of the swing, and how far one period's mean is from
another's.

A mean over a window that does not hold whole periods is biased by the part period it
holds: with a swing of amplitude a and n periods in the window, by up to about a / (pi n).
Averaging from one rise of the swing through its mean to a later one removes that bias
for a periodic swing. The single periods' means then say how periodic the swing is: equal
for a strictly periodic one; for one that varies from period to period, their standard
deviation over the square root of their number is the standard error of the mean (the
periods taken as the batches of a batch-means estimate).
"""
from dataclasses import dataclass

import numpy as np

from .errors import HarnessError


def interval_mean(t, s, a, b):
    """The mean over [a, b] of s, taken as linear between its samples at times t."""
    inside = (t > a) & (t < b)
    tt = np.concatenate(([a], t[inside], [b]))
    ss = np.interp(tt, t, s)
    return float(np.sum((ss[1:] + ss[:-1]) * np.diff(tt)) / (2.0 * (b - a)))


def rises(t, s, level, hysteresis):
    """The times at which s rises through `level` (linear between samples), each counted only
    when s has been below level - hysteresis since the rise before: a ripple about the level
    does not start a period."""
    out, armed = [], False
    for i in range(1, len(s)):
        if s[i - 1] < level - hysteresis:
            armed = True
        if armed and s[i - 1] < level <= s[i]:
            out.append(float(t[i - 1] + (level - s[i - 1]) * (t[i] - t[i - 1]) / (s[i] - s[i - 1])))
            armed = False
    return out


@dataclass
class PeriodAverage:
    """The means of a history's columns over the whole periods of its swing.

    periods: the whole periods averaged over (0: fewer than two were found, and the
    means are over the whole window instead); period_means: each period's mean of each
    column (periods x columns; empty with no periods); start, end: the times averaged
    between; reference: the column whose rises bound the periods; window: the samples
    after the transient (rows x columns)."""
    means: np.ndarray
    period_means: np.ndarray
    periods: int
    start: float
    end: float
    reference: int
    window: np.ndarray

    def standard_error(self, column_weights):
        """How far the mean of sum_c w_c column_c can still be from the history's long-time
        mean: the standard deviation of the periods' means over the square root of their
        number. With fewer than two periods, half the range of the window's samples (the
        steady iteration's measure: a history that neither swings nor settles)."""
        w = np.asarray(column_weights, float)
        if self.periods >= 2:
            return float(np.std(self.period_means @ w, ddof=1) / np.sqrt(self.periods))
        return 0.5 * float(np.ptp(self.window @ w))


def period_average(t, columns, discard):
    """Averages the columns of a history (rows at times t) over the whole periods after the
    first `discard` time units (the start's transient). The periods are bounded by the rises
    of one column through its mean over the window, with a hysteresis of a quarter of its
    standard deviation: of the columns that swing at least half as much as the one that
    swings most, the one with the most rises (a mirror-image point, whose columns swing
    alike, then picks the same one, and the most of the window is used). Refuses a window
    of fewer than two samples."""
    t = np.asarray(t, float)
    columns = np.atleast_2d(np.asarray(columns, float))
    if columns.shape[0] != t.size:
        columns = columns.T
    keep = t >= t[0] + discard
    tw, cw = t[keep], columns[keep]
    if tw.size < 2:
        raise HarnessError(f"a history of {t.size} samples from t = {t[0]:g} to {t[-1]:g} has fewer than two "
                           f"after the {discard:g} time units left out as the start's transient")
    deviation = cw.std(axis=0)
    bounds, ref = [], int(np.argmax(deviation))
    if deviation[ref] > 0:
        strong = [c for c in range(cw.shape[1]) if deviation[c] >= 0.5 * deviation[ref]]
        found = {c: rises(tw, cw[:, c], float(cw[:, c].mean()), 0.25 * float(deviation[c])) for c in strong}
        ref = max(strong, key=lambda c: (len(found[c]), deviation[c]))
        bounds = found[ref]
    if len(bounds) >= 3:
        period_means = np.array([[interval_mean(tw, cw[:, c], a, b) for c in range(cw.shape[1])]
                                 for a, b in zip(bounds[:-1], bounds[1:])])
        spans = np.diff(bounds)
        means = (spans @ period_means) / spans.sum()
        return PeriodAverage(means, period_means, len(bounds) - 1, bounds[0], bounds[-1], ref, cw)
    means = np.array([interval_mean(tw, cw[:, c], tw[0], tw[-1]) for c in range(cw.shape[1])])
    return PeriodAverage(means, np.empty((0, cw.shape[1])), 0, float(tw[0]), float(tw[-1]), ref, cw)
