"""The closed set of comparators. Each takes the extracted value, the reference and
the tolerance, and returns computed, reference, delta and pass (plus plot data)."""
import math

import numpy as np

from .errors import HarnessError


class Curve:
    """Sampled data y(x), e.g. Cf along a plate or u/U_e across a boundary layer; `yerr`, when
    given, is each point's half-band of uncertainty (a sweep point's iteration error)."""

    def __init__(self, x, y, label="", yerr=None):
        self.x, self.y, self.label = np.asarray(x, float), np.asarray(y, float), label
        self.yerr = None if yerr is None else np.asarray(yerr, float)
        if self.x.size == 0:
            raise HarnessError(f"extracted curve '{label}' is empty (check the range)")


class Family:
    """Values of one quantity on a grid family: spacing h (coarse to fine) and value."""

    def __init__(self, h, values, label=""):
        order = np.argsort(-np.asarray(h, float))
        self.h = np.asarray(h, float)[order]
        self.values = np.asarray(values, float)[order]
        self.label = label


def _scalar(v, what):
    if isinstance(v, (Curve, Family)) or v is None:
        raise HarnessError(f"{what} must be a single number")
    return float(v)


def _reference_on(curve, ref):
    if callable(ref):
        return np.array([ref(x) for x in curve.x])
    if isinstance(ref, Curve):
        lo, hi = ref.x.min(), ref.x.max()
        inside = (curve.x >= lo) & (curve.x <= hi)
        if not inside.all():
            raise HarnessError(f"computed points outside the reference range [{lo}, {hi}]")
        order = np.argsort(ref.x)  # reference tables may run either way
        return np.interp(curve.x, ref.x[order], ref.y[order])
    raise HarnessError("a profile comparison needs a reference curve or function")


def observed_orders(family):
    h, e = family.h, np.abs(family.values)
    return [math.log(e[i] / e[i + 1]) / math.log(h[i] / h[i + 1]) for i in range(len(h) - 1)]


def gci(family, safety=1.25):
    """Roache's grid convergence index of the finest grid from the three finest grids
    (Roache 1994/1998; the fixed-point order for non-constant refinement ratios as in
    Celik et al. 2008). Returns (gci_fine, observed_order, extrapolated_value)."""
    if len(family.h) < 3:
        raise HarnessError("gci needs at least three grids")
    h3, h2, h1 = family.h[-3:]
    f3, f2, f1 = family.values[-3:]
    r21, r32 = h2 / h1, h3 / h2
    e21, e32 = f2 - f1, f3 - f2
    if e21 == 0.0 or e32 == 0.0:
        raise HarnessError("gci: two grids give identical values; no convergence information")
    s = math.copysign(1.0, e32 / e21)
    p = math.log(abs(e32 / e21)) / math.log(r21)
    for _ in range(100):
        q = math.log((r21 ** p - s) / (r32 ** p - s))
        p_new = abs(math.log(abs(e32 / e21)) + q) / math.log(r21)
        if abs(p_new - p) < 1e-12:
            break
        p = p_new
    f_ext = (r21 ** p * f1 - f2) / (r21 ** p - 1.0)
    ea = abs((f1 - f2) / f1)
    return safety * ea / (r21 ** p - 1.0), p, f_ext


def compare(comparator, computed, reference, tolerance, options):
    out = {"plot": None}
    if comparator in ("abs", "rel"):
        c = _scalar(computed, "computed value")
        r = _scalar(reference, "reference value")
        if comparator == "abs":
            delta = c - r
        else:
            if r == 0.0:
                raise HarnessError("rel comparator with a zero reference")
            delta = c / r - 1.0
        out.update(computed=c, reference=r, delta=delta, passed=bool(abs(delta) <= tolerance))
    elif comparator in ("profile_rms", "profile_max"):
        if not isinstance(computed, Curve):
            raise HarnessError("profile comparators need an extracted curve")
        ref = _reference_on(computed, reference)
        relative = options.get("relative", True)
        err = computed.y / ref - 1.0 if relative else computed.y - ref
        delta = float(np.sqrt(np.mean(err ** 2))) if comparator == "profile_rms" else float(np.max(np.abs(err)))
        worst = int(np.argmax(np.abs(err)))
        out.update(computed=float(computed.y[worst]), reference=float(ref[worst]), delta=delta,
                   passed=bool(delta <= tolerance), points=int(computed.x.size),
                   plot={"kind": "curve", "x": computed.x.tolist(), "y": computed.y.tolist(), "ref": ref.tolist(),
                         "err": err.tolist(), "relative": relative})
    elif comparator == "observed_order":
        if not isinstance(computed, Family):
            raise HarnessError("observed_order needs a grid family")
        orders = observed_orders(computed)
        pairs = int(options.get("pairs", 2))
        if len(orders) < pairs:
            raise HarnessError(f"observed_order over {pairs} pairs needs {pairs + 1} grids, got {len(computed.h)}")
        c = min(orders[-pairs:])
        r = _scalar(reference, "theoretical order")
        out.update(computed=float(c), reference=r, delta=float(c - r), passed=bool(c >= r - tolerance),
                   orders=[float(o) for o in orders],
                   plot={"kind": "family", "h": computed.h.tolist(), "values": computed.values.tolist(),
                         "orders": orders, "theory": r})
    elif comparator == "gci":
        if not isinstance(computed, Family):
            raise HarnessError("gci needs a grid family")
        g, p, f_ext = (float(v) for v in gci(computed, float(options.get("safety_factor", 1.25))))
        out.update(computed=g, reference=None if reference is None else _scalar(reference, "reference"),
                   delta=g, passed=bool(g <= tolerance), observed_order=p, extrapolated=f_ext,
                   plot={"kind": "family", "h": computed.h.tolist(), "values": computed.values.tolist(),
                         "orders": [float(o) for o in observed_orders(computed)] if np.all(computed.values != 0) else [],
                         "theory": None, "extrapolated": f_ext})
    elif comparator == "family_spread":
        # A family already converged below what its differences can order (a GCI would
        # divide round-off by round-off): every member within `tolerance` of the finest.
        if not isinstance(computed, Family):
            raise HarnessError("family_spread needs a family of runs")
        finest = float(computed.values[-1])
        if finest == 0.0:
            raise HarnessError("family_spread: the finest run's value is zero; a relative spread is undefined")
        spread = float(np.max(np.abs(computed.values - finest)) / abs(finest))
        out.update(computed=spread, reference=None if reference is None else _scalar(reference, "reference"),
                   delta=spread, passed=bool(spread <= tolerance),
                   plot={"kind": "family", "h": computed.h.tolist(), "values": computed.values.tolist(),
                         "orders": [], "theory": None, "extrapolated": None})
    elif comparator in ("max", "min"):
        # One-sided bounds (requirements such as "at most 40 cycles", "at least 5x faster").
        c = _scalar(computed, "computed value")
        ok = c <= tolerance if comparator == "max" else c >= tolerance
        out.update(computed=c, reference=None if reference is None else _scalar(reference, "reference"),
                   delta=c - tolerance, passed=bool(ok), plot=getattr(computed, "plot", None))
    elif comparator == "restart_equal":
        c = _scalar(computed, "history difference")
        out.update(computed=c, reference=0.0, delta=c, passed=bool(c <= tolerance))
    else:
        raise HarnessError(f"unknown comparator {comparator!r}")
    out["pass"] = out.pop("passed")
    return out
