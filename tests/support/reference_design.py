"""The test suites' one reference for the paper's second-order filter (eq. 15), shared by the
meshlabserver integration harness and the command-line tool harness (C++ twin:
reference_design.h). The coefficients come from solving the five design conditions as a
linear system, not from the closed form the core uses, so a wrong closed form disagrees with
this instead of agreeing with a copy of itself."""

import numpy as np


def eq15_coefficients(s1, s2, G0, G1, Ginf):
    """(a0, a1, a2, b0, b1, b2) of G(s) = (b0 + b1 s + b2 s^2) / (a0 + a1 s + a2 s^2), a0 = 1, from
        G(0) = G0:      b0 = G0
        G(s1) = G1:     N(s1) - G1 D(s1) = 0
        G'(s1) = 0:     N'(s1) - G1 D'(s1) = 0   (given the line above)
        G(s2) = 1:      N(s2) - D(s2) = 0
        G(inf) = Ginf:  b2 - Ginf a2 = 0
    Raises numpy.linalg.LinAlgError when the conditions are not independent (e.g. s1 = s2)."""
    # In t = s / s1 every entry is O(1); the coefficient of t^k is that of s^k times s1^k.
    t2 = s2 / s1
    # Unknowns (a1, a2, b0, b1, b2).
    A = np.array([
        [0.0, 0.0, 1.0, 0.0, 0.0],
        [-G1, -G1, 1.0, 1.0, 1.0],
        [-G1, -2 * G1, 0.0, 1.0, 2.0],
        [-t2, -t2 * t2, 1.0, t2, t2 * t2],
        [0.0, -Ginf, 0.0, 0.0, 1.0],
    ])
    rhs = np.array([G0, G1, 0.0, 1.0, 0.0])
    if np.linalg.matrix_rank(A) < 5:
        raise np.linalg.LinAlgError("eq. 15: the five conditions are not independent")
    a1, a2, b0, b1, b2 = np.linalg.solve(A, rhs)
    return 1.0, a1 / s1, a2 / s1 ** 2, b0, b1 / s1, b2 / s1 ** 2


def eq15_gain(s, s1, s2, G0, G1, Ginf):
    """G(s) of eq. 15 for a number or a numpy array s."""
    a0, a1, a2, b0, b1, b2 = eq15_coefficients(s1, s2, G0, G1, Ginf)
    s = np.asarray(s, dtype=float)
    return (b0 + s * (b1 + s * b2)) / (a0 + s * (a1 + s * a2))
