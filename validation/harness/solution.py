"""Reads a narwhal solution.cgns (CGNS/HDF5) with h5py: nodes, cell-centred fields,
cell centres and exact hexahedron volumes (NUMERICS §2.3), per zone."""
import h5py
import numpy as np

FIELDS = {"p": "Pressure", "u": "VelocityX", "v": "VelocityY", "w": "VelocityZ"}


class Zone:
    def __init__(self, name, x, fields, ordinal=0):
        self.name = name
        self.ordinal = ordinal  # the block's place in the run's block order (CGNS Ordinal_t)
        self.x = x            # nodes, shape (nk+1, nj+1, ni+1, 3)
        self.fields = fields  # name -> (nk, nj, ni)
        c = x
        self.centres = 0.125 * (c[:-1, :-1, :-1] + c[1:, :-1, :-1] + c[:-1, 1:, :-1] + c[:-1, :-1, 1:]
                                + c[1:, 1:, :-1] + c[1:, :-1, 1:] + c[:-1, 1:, 1:] + c[1:, 1:, 1:])
        self.volumes = _hex_volumes(x)


def _face(a, b, c, d):
    s = 0.5 * np.cross(c - a, d - b)
    m = 0.25 * (a + b + c + d)
    return s, m


def _hex_volumes(X):
    # Arrays indexed [k, j, i]; faces as in NUMERICS §2.2 (i, j, k node orders).
    def n(di, dj, dk):
        nk, nj, ni = X.shape[0] - 1, X.shape[1] - 1, X.shape[2] - 1
        return X[dk:dk + nk, dj:dj + nj, di:di + ni]
    vol = 0.0
    for sign, base in ((-1, 0), (1, 1)):
        s, m = _face(n(base, 0, 0), n(base, 1, 0), n(base, 1, 1), n(base, 0, 1))
        vol = vol + sign * np.sum(s * m, axis=-1)
        s, m = _face(n(0, base, 0), n(0, base, 1), n(1, base, 1), n(1, base, 0))
        vol = vol + sign * np.sum(s * m, axis=-1)
        s, m = _face(n(0, 0, base), n(1, 0, base), n(1, 1, base), n(0, 1, base))
        vol = vol + sign * np.sum(s * m, axis=-1)
    return vol / 3.0


def read_solution(path, extra=()):
    """The zones of a solution, in file order, with p, u, v, w and the CGNS fields named in
    `extra` (name -> (nk, nj, ni) arrays, under their CGNS names)."""
    zones = []
    with h5py.File(path, "r") as f:
        base = f["Base"]
        for name in base:
            z = base[name]
            if z.attrs.get("label", b"") != b"Zone_t":
                continue
            x = _nodes(z)
            fs = z["FlowSolution"]
            fields = {k: fs[v][" data"][()] for k, v in FIELDS.items()}
            fields.update({v: fs[v][" data"][()] for v in extra})
            ordinal = int(z["Ordinal"][" data"][()][0]) if "Ordinal" in z else 0
            zones.append(Zone(name, x, fields, ordinal))
    return zones


def read_nodes(path):
    """Zone name -> nodes (nk+1, nj+1, ni+1, 3) of a grid or solution file."""
    out = {}
    with h5py.File(path, "r") as f:
        for name, z in f["Base"].items():
            if z.attrs.get("label", b"") == b"Zone_t":
                out[name] = _nodes(z)
    return out


def _nodes(zone):
    gc = zone["GridCoordinates"]
    return np.stack([gc[c][" data"][()] for c in ("CoordinateX", "CoordinateY", "CoordinateZ")], axis=-1)
