"""Extractors of fully developed duct flow on a box grid periodic in x (the square-duct
rungs): bulk quantities, profiles along the wall bisector and the diagonal, the
secondary flow and its vortex cells. Lengths are in the half-width h (centre at 0,
walls at +-1) and velocities in the bulk velocity U_b of the run itself."""
import json

import numpy as np

from .compare import Curve
from .errors import HarnessError
from .schema import extractor
from .reference import ReferenceFile


class Annotated(float):
    """A scalar result that carries plot data for the report."""

    def __new__(cls, value, plot):
        obj = super().__new__(cls, value)
        obj.plot = plot
        return obj


class Section:
    """The cross-section (first streamwise cell layer) of a single-block duct: cell
    centres y[k, j], z[k, j], velocities, areas and U_b."""

    def __init__(self, zone):
        if zone.x.shape[2] < 2:
            raise HarnessError("duct extraction: the zone has no streamwise cell")
        c = zone.centres[:, :, 0]
        self.y, self.z = c[..., 1], c[..., 2]
        self.z_nodes = zone.x[:, 0, 0, 2]
        self.u, self.v, self.w = (zone.fields[n][:, :, 0] for n in "uvw")
        dx = np.abs(zone.x[1:, 1:, 1:, 0] - zone.x[1:, 1:, :-1, 0])[:, :, 0]
        self.area = zone.volumes[:, :, 0] / dx
        self.ub = float(np.sum(self.area * self.u) / np.sum(self.area))
        self.nk, self.nj = self.u.shape
        if self.nj % 2 or self.nk % 2 or self.nj != self.nk:
            raise HarnessError("duct extraction needs a square cross-section with an even cell count per side")
        if not np.allclose(self.y[0, :], self.z[:, 0], atol=1e-12):
            raise HarnessError("duct extraction needs the same node distribution in y and z")


def _section(ctx, run_id):
    zones = ctx.solution(run_id)
    if len(zones) != 1:
        raise HarnessError("duct extraction expects a single-block duct")
    return Section(zones[0])


def _body_force(ctx, run_id):
    with open(ctx.run_dir(run_id) / "run.json") as f:
        data = json.load(f)
    if "body_force" not in data:
        raise HarnessError(f"run.json of '{run_id}' has no body_force")
    return float(data["body_force"][0])


def _wall_bisector(s):
    """Mean over the four half-bisectors of (distance from the wall, U/U_b, wall-normal
    velocity / U_b positive toward the wall). The centreline lies between the two middle
    cell rows; their mean is its value to second order."""
    m = s.nj // 2
    line_z0 = (0.5 * (s.u[m - 1, :] + s.u[m, :]), 0.5 * (s.v[m - 1, :] + s.v[m, :]))  # along y at z = 0
    line_y0 = (0.5 * (s.u[:, m - 1] + s.u[:, m]), 0.5 * (s.w[:, m - 1] + s.w[:, m]))  # along z at y = 0
    yc = s.y[0, :]
    dist = 1.0 - np.abs(yc[m:])  # upper halves, centre to wall reversed below
    u = np.zeros(m)
    vn = np.zeros(m)
    for (ul, vl) in (line_z0, line_y0):
        # Upper half: wall at +1, toward the wall = +velocity; lower half mirrored.
        u += ul[m:] + ul[m - 1::-1]
        vn += vl[m:] - vl[m - 1::-1]
    order = np.argsort(dist)
    return dist[order], (u / 4.0 / s.ub)[order], (vn / 4.0 / s.ub)[order]


def _diagonal(s):
    """Mean over the four half-diagonals of (t = |y| = |z|, U/U_b, velocity along the
    diagonal toward the corner / U_b)."""
    n, m = s.nj, s.nj // 2
    j = np.arange(m, n)
    jm = n - 1 - j
    t = np.abs(s.y[0, j])
    u = (s.u[j, j] + s.u[jm, jm] + s.u[jm, j] + s.u[j, jm]) / 4.0
    # toward the corner (sy, sz)/sqrt 2 for the corner in quadrant (sign y, sign z)
    vd = ((s.v[j, j] + s.w[j, j]) - (s.v[jm, jm] + s.w[jm, jm]) + (s.v[jm, j] - s.w[jm, j])
          + (-s.v[j, jm] + s.w[j, jm])) / (4.0 * np.sqrt(2.0))
    return t, u / s.ub, vd / s.ub


def stream_function(s):
    """psi with v = d psi/dz, w = -d psi/dy, integrated along z from the wall z = -1
    (psi = 0 there) at the cell centres in y and the nodes in z: [k node, j cell]."""
    dz = np.diff(s.z_nodes)
    psi = np.zeros((s.nk + 1, s.nj))
    psi[1:, :] = np.cumsum(s.v * dz[:, None], axis=0)
    return psi


def count_cells(field, threshold):
    """Connected regions (4-neighbour) where field > threshold or field < -threshold."""
    count = 0
    for sign in (1.0, -1.0):
        mask = sign * field > threshold
        seen = np.zeros_like(mask)
        for start in zip(*np.nonzero(mask)):
            if seen[start]:
                continue
            count += 1
            stack = [start]
            seen[start] = True
            while stack:
                a, b = stack.pop()
                for da, db in ((1, 0), (-1, 0), (0, 1), (0, -1)):
                    p, q = a + da, b + db
                    if 0 <= p < mask.shape[0] and 0 <= q < mask.shape[1] and mask[p, q] and not seen[p, q]:
                        seen[p, q] = True
                        stack.append((p, q))
    return count


def _dns_field(ctx, spec):
    """The DNS quadrant mirrored to the whole duct, for the picture only."""
    dns = spec.get("dns")
    if not dns:
        return None
    ref = ReferenceFile(ctx.reference_root, dns["file"])
    rows = ref.rows_where(dns.get("where", {}))
    y, z = ref.column("y_over_h", rows), ref.column("z_over_h", rows)
    U, V, W = (ref.column(c, rows) for c in ("U_over_Ub", "V_over_Ub", "W_over_Ub"))
    ys, zs = np.unique(y), np.unique(z)
    grid = lambda a: np.full((zs.size, ys.size), np.nan)  # noqa: E731
    Ug, Vg, Wg = grid(0), grid(0), grid(0)
    jy, kz = np.searchsorted(ys, y), np.searchsorted(zs, z)
    Ug[kz, jy], Vg[kz, jy], Wg[kz, jy] = U, V, W
    yf = np.concatenate((-ys[::-1], ys))
    zf = np.concatenate((-zs[::-1], zs))
    def mirror(a, sy, sz):
        top = np.concatenate((sy * a[:, ::-1], a), axis=1)
        return np.concatenate((sz * top[::-1, :], top), axis=0)
    return {"y": yf.tolist(), "z": zf.tolist(), "u": mirror(Ug, 1, 1).tolist(),
            "v": mirror(Vg, -1, 1).tolist(), "w": mirror(Wg, 1, -1).tolist()}


@extractor("duct_flow", "quantity", "hydraulic_diameter", "threshold", "dns")
def duct_flow(ctx, spec, run_id):
    """quantity: f_darcy (2 G D_h / U_b^2 with the run's final body force G),
    secondary_max_pct (max in-plane speed / U_b x 100), wall_bisector (U/U_b against
    the distance from the wall / h), bisector_normal_pct (wall-normal velocity, toward
    the wall, x 100), diagonal (U/U_b against t = |y|/h), diagonal_secondary_pct, or
    vortex_cells (regions of the secondary stream function beyond `threshold` of its
    maximum, with the isovel/vector picture beside the DNS field `dns`)."""
    s = _section(ctx, run_id)
    q = spec.get("quantity")
    if q == "f_darcy":
        dh = float(spec.get("hydraulic_diameter", 2.0))
        return 2.0 * _body_force(ctx, run_id) * dh / s.ub ** 2
    if q == "secondary_max_pct":
        return 100.0 * float(np.max(np.hypot(s.v, s.w))) / s.ub
    if q in ("wall_bisector", "bisector_normal_pct"):
        d, u, vn = _wall_bisector(s)
        return Curve(d, u, "U/U_b(y/h)") if q == "wall_bisector" else Curve(d, 100.0 * vn, "V_n/U_b %")
    if q in ("diagonal", "diagonal_secondary_pct"):
        t, u, vd = _diagonal(s)
        order = np.argsort(t)
        return Curve(t[order], (u if q == "diagonal" else 100.0 * vd)[order], q)
    if q == "vortex_cells":
        psi = stream_function(s)
        n = count_cells(psi, float(spec.get("threshold", 0.05)) * float(np.max(np.abs(psi))))
        step = max(1, s.nj // 24)
        plot = {"kind": "duct_field", "y": s.y[0, :].tolist(), "z": s.z[:, 0].tolist(),
                "u": (s.u / s.ub).tolist(), "v": (s.v / s.ub).tolist(), "w": (s.w / s.ub).tolist(),
                "psi": psi.tolist(), "step": step, "cells": n, "dns": _dns_field(ctx, spec)}
        return Annotated(n, plot)
    raise HarnessError("duct_flow: quantity must be f_darcy, secondary_max_pct, wall_bisector, "
                       "bisector_normal_pct, diagonal, diagonal_secondary_pct or vortex_cells")
