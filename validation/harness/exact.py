"""Exact solutions used by verification rungs, written independently of the solver
from NUMERICS.md: §12.2 manufactured solution, §12.3 Couette and Poiseuille."""
import numpy as np


def mms(x, y, z, a=(1.0, 1.0, -2.0), p0=1.0):
    cx, cy, cz = np.cos(np.pi * x), np.cos(np.pi * y), np.cos(np.pi * z)
    sx, sy, sz = np.sin(np.pi * x), np.sin(np.pi * y), np.sin(np.pi * z)
    return {"p": p0 * cx * cy * cz, "u": a[0] * cx * sy * sz, "v": a[1] * sx * cy * sz, "w": a[2] * sx * sy * cz}


def couette(x, y, z, wall_speed=1.0, height=1.0):
    zero = np.zeros_like(x)
    return {"p": zero, "u": wall_speed * y / height, "v": zero, "w": zero}


def poiseuille(x, y, z, reynolds=1.0, gradient=1.0, height=1.0):
    zero = np.zeros_like(x)
    return {"p": zero, "u": 0.5 * reynolds * gradient * y * (height - y), "v": zero, "w": zero}


SOLUTIONS = {"mms": mms, "couette": couette, "poiseuille": poiseuille}
