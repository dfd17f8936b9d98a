"""Potential flow about a body of revolution at zero incidence: an independent reference for
a body's surface pressure where the boundary layer is thin (a forebody at high Re).

Constant-strength vortex-ring panels on the meridian; the Stokes stream function vanishes at
each panel's midpoint (the body is the streamline psi = 0 of U = 1 along +x), so the flow
inside is at rest and the speed just outside equals the sheet strength: Cp = 1 - gamma^2.
Ring formulas: the stream function of a ring of unit circulation, radius a, at (x, r),
psi = sqrt(A) ((1 - m/2) K(m) - E(m)) / (2 pi), A = (r + a)^2 + (x - x0)^2, m = 4 a r / A
(Lamb, Hydrodynamics §161). Converges at first order in the panel size (tests: the 6:1
spheroid against its exact solution)."""
import numpy as np

_GAUSS = np.polynomial.legendre.leggauss(8)


def complete_elliptic_integrals(m):
    """K(m) and E(m), parameter m = k^2 in [0, 1), by the arithmetic-geometric mean."""
    a, b, c = np.ones_like(m), np.sqrt(1.0 - m), np.sqrt(m)
    weighted, power = 0.5 * c * c, 0.5
    for _ in range(40):
        a, b, c = 0.5 * (a + b), np.sqrt(a * b), 0.5 * (a - b)
        power *= 2.0
        weighted = weighted + power * c * c
        if np.all(np.abs(c) < 1e-16):
            break
    k = np.pi / (2.0 * a)
    return k, k * (1.0 - weighted)


def ring_stream_function(x0, a, x, r):
    """Stokes stream function at (x, r) of a vortex ring of unit circulation and radius a at x0."""
    big_a = (r + a) ** 2 + (x - x0) ** 2
    m = np.clip(4.0 * a * r / big_a, 0.0, 1.0 - 1e-16)
    k, e = complete_elliptic_integrals(m)
    return np.sqrt(big_a) * ((1.0 - 0.5 * m) * k - e) / (2.0 * np.pi)


def surface_cp(x_nodes, r_nodes):
    """Cp at the midpoints of the meridian's panels (nodes from pole to pole, r >= 0):
    (x_mid, r_mid, cp)."""
    x_nodes, r_nodes = np.asarray(x_nodes, float), np.asarray(r_nodes, float)
    xm, rm = 0.5 * (x_nodes[1:] + x_nodes[:-1]), 0.5 * (r_nodes[1:] + r_nodes[:-1])
    tx, tr = np.diff(x_nodes), np.diff(r_nodes)
    ds = np.hypot(tx, tr)
    if np.any(ds <= 0.0):
        raise ValueError("surface_cp: repeated meridian nodes")
    tx, tr = tx / ds, tr / ds
    g, w = _GAUSS
    # Each panel integrated in two halves, so that the quadrature stays clear of its own
    # midpoint, where the kernel has a logarithmic singularity.
    s = np.concatenate([0.25 * (g - 1.0), 0.25 * (g + 1.0)])
    ws = np.concatenate([0.25 * w, 0.25 * w])
    influence = np.empty((len(xm), len(xm)))
    for j in range(len(xm)):
        xq, rq = xm[j] + s * tx[j] * ds[j], rm[j] + s * tr[j] * ds[j]
        psi = ring_stream_function(xq[None, :], rq[None, :], xm[:, None], rm[:, None])
        influence[:, j] = psi @ (ws * ds[j])
    gamma = np.linalg.solve(influence, -0.5 * rm ** 2)  # the free stream's psi is r^2 / 2
    return xm, rm, 1.0 - gamma ** 2


def cosine_nodes(radius, n):
    """n panels clustered at both poles of a body of unit length whose radius at x is radius(x)."""
    x = 0.5 * (1.0 - np.cos(np.linspace(0.0, np.pi, n + 1)))
    r = np.asarray(radius(x), float)
    r[0] = r[-1] = 0.0
    return x, r
