"""Rounding bounds for tolerances that depend on LAPACK, BLAS or the CPU (tolerance audit, issue 13).

A test that compares a LAPACK result (eigen-solve, linear solve, inverse) or a BLAS product with a
closed form, or two such computations with each other, may not assume the last bits of one machine:
the libraries choose blocking, summation order and fused multiply-adds by CPU. These bounds follow
the backward-error analysis of the routine (Higham, *Accuracy and Stability of Numerical Algorithms*,
2nd ed.; Demmel, *Applied Numerical Linear Algebra*): the computed answer is exact for data
perturbed by ``p(n) eps`` relative, and the answer moves by that times the problem's condition
number. ``p(n)`` is a small multiple of the size; ``SAFETY = 16`` covers the constants.
See docs/tolerance-audit.md.
"""

from __future__ import annotations

import numpy as np

EPS = float(np.finfo(float).eps)
SAFETY = 16.0


def solve_rel(A) -> float:
    """Relative rounding of x = A^-1 b (or of A^-1): SAFETY n eps cond(A) (backward-stable LU/Cholesky)."""
    A = np.atleast_2d(np.asarray(A, dtype=float))
    return SAFETY * A.shape[0] * EPS * float(np.linalg.cond(A))


def sym_eig_rel(lam, n: int | None = None) -> np.ndarray:
    """Relative rounding of the eigenvalues lam of a symmetric(-definite, mass-scaled) problem:
    Weyl's theorem gives |d lam_i| <= ||E|| <= SAFETY n eps max |lam|, so relative to lam_i the bound
    is SAFETY n eps max |lam| / |lam_i| (small eigenvalues of a wide spectrum are the least accurate)."""
    lam = np.asarray(lam, dtype=float)
    n = lam.size if n is None else n
    return SAFETY * n * EPS * np.max(np.abs(lam)) / np.abs(lam)


def dot_abs(a, b) -> float:
    """Absolute rounding of a sum of products sum_i a_i b_i in any order: SAFETY n eps sum |a_i b_i|."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return SAFETY * a.size * EPS * float(np.sum(np.abs(a * b)))
