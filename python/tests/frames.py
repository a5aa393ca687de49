"""Small rigid-transform helpers shared by the tests (rotations about one axis, 4x4 transforms)."""
import numpy as np


def rot(axis, angle):
    """Rotation by `angle` [rad] about axis 0 (x), 1 (y) or 2 (z)."""
    c, s = np.cos(angle), np.sin(angle)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    r = np.eye(3)
    r[i, i], r[i, j], r[j, i], r[j, j] = c, -s, s, c
    return r


def transform(r, t):
    """The 4x4 transform of rotation `r` and translation `t`."""
    m = np.eye(4)
    m[:3, :3], m[:3, 3] = r, t
    return m
