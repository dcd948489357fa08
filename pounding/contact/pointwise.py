"""Force laws of one contact point, and the implicit solve of the end-of-step forces.

A *pointwise* law gives the force of a contact from that contact's own state: its penetration
delta [m] (> 0 in contact), the penetration's rate delta' [m/s] (> 0 approaching), the rate when
the contact began delta'_0 [m/s], and the law's parameters. Each law is one compiled leaf kernel

    force, d_force_d_delta, d_force_d_rate = law_force(delta, rate, approach_rate, params)

(``params`` a float64 array, built per point by the law class from its stiffness, exponent,
restitution and the point's effective mass), and one :class:`PointwiseLaw` subclass that says how
to build ``params``. The force is zero for delta <= 0 and never negative unless the law says it may
pull (Kelvin's ``tension = true``).

Glossary (units)
----------------
delta
    Penetration, -gap [m]: how far the slabs overlap along the contact normal.
rate
    delta' [m/s]; > 0 while the slabs approach, < 0 while they separate.
approach_rate
    delta'_0 [m/s], the closing speed when the contact began (> 0 for an impact).
m_eff
    Effective mass of the contact [kg], 1 / a with a = w.w the Delassus entry of the point's
    modal row (m1 m2 / (m1 + m2) for two floors moving along the normal).
k, k_h
    Contact stiffness [N/m] (linear) or [N/m^n] (Hertz-type, n the exponent).

The face rule
-------------
The law gives the force of one *contact*: two slabs pressed together at one storey. Where they
meet face to face the geometry gives several points (the ends of the common facade), each with
its own penetration; each point carries a share s_i of the law, fixed by the slabs' rest
geometry (``ContactState.share``, :mod:`pounding.framework.engine.face_shares`),

    lambda_i = s_i F(delta_i, delta'_i, delta'_0; m_eff,i),     m_eff,i = 1 / W_ii,

s_i = 1/2 at each end of a face, so that a uniform penetration of a face (both ends with the
same row, W_ii = a) gives the law's force F(delta; 1 / a), as one point would; s_i = 1 at a
corner that ends no face. With rotation the points' penetrations differ and each carries its
share at its own penetration; an end of a face that presses alone (the other lifted off) keeps
its half, half the face's spring and dashpot. Because a point's share never changes while it
presses, the force of an elastic law derives from the potential sum_i s_i integral_0^delta_i F:
the contact gives back what it stored. (Sharing the law equally among the m points pressed in a
step made the remaining end's share jump from 1/2 to 1 as the other lifted off: a force jump
without any deformation, which let an elastic law create energy.)

The solve
---------
The engine gives, at the end of a trial step, the penetrations delta_0 and rates delta'_0 the
points would have without contact forces, and their compliances S_q, S_v (m, m) to end-of-step
forces (a force vector lambda moves the gaps by S_q lambda, so delta = delta_0 - S_q lambda).
:func:`~pounding.contact.newton.solve_forces` finds lambda with lambda_i = s_i F_i(delta(lambda), delta'(lambda))
by Newton's method on that residual with the law's tangent, backtracking on its norm: the
residual is monotone (every law's force grows with delta and delta', and S_q, S_v are positive
semidefinite), so the solution is unique.

A contact's force point by point is a :class:`PointLaw`: one or more compiled kernels acting in
parallel, each on the penetration less its own shift (a bumper's layer, and the slabs' law once
the layer is compressed by c t: :mod:`pounding.contact.bumper`). The solve is one compiled
function that takes the kernels as a tuple (:mod:`pounding.compiler.unroll`: compiled once per
tuple of kernels, each inlined), or the same function run as Python around a kernel only Python
knows (a third party's law written without the compiler).
"""

from __future__ import annotations

import math
from typing import ClassVar, NamedTuple

import numpy as np

from pounding.compiler import interpreted, is_compiled, njit
from pounding.compiler.unroll import LawTuple, kernel_tuple, literal_unroll, unrolled_in
from pounding.contact.base import ContactLaw
from pounding.contact.newton import solve_forces
from pounding.errors import InputError

unrolled_in(globals())  # this module's literal_unroll: numba's once numba is set up

#: default Hertz stiffness of two concrete slabs [N/m^1.5]: Jankowski (2005), fitted to impact
#: tests of concrete members (Earthquake Eng. Struct. Dyn. 34, 595-611)
CONCRETE_HERTZ_STIFFNESS = 2.75e9


def check_stiffness(value, unit: str) -> float:
    """``value`` as a float if it is a finite positive stiffness, else :class:`InputError` on ``stiffness``."""
    if not (isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value) and value > 0):
        raise InputError(f"expected a positive contact stiffness [{unit}], got {value!r}", field="stiffness")
    return float(value)


def check_exponent(value) -> float:
    """``value`` as a float if it is an exponent in (0, 3], else :class:`InputError` on ``exponent``."""
    if not (isinstance(value, (int, float)) and not isinstance(value, bool) and 0.0 < value <= 3.0):
        raise InputError(f"expected a force exponent n in (0, 3] (1.5 for Hertz), got {value!r}", field="exponent")
    return float(value)


def check_positive_restitution(value: float) -> float:
    """``value`` if it is a restitution in (0, 1] (a law whose damping divides by it), else :class:`InputError`."""
    if not value > 0.0:
        raise InputError(f"expected a coefficient of restitution in (0, 1] (this law's damping divides by it), got {value!r}",
                         field="restitution")
    return value


def check_tolerance(value) -> float:
    """``value`` as a float if it is a length tolerance in (0, 1) m, else :class:`InputError` on ``tolerance``."""
    if not (isinstance(value, (int, float)) and not isinstance(value, bool) and 0 < value < 1):
        raise InputError(f"expected a length tolerance in (0, 1) m, got {value!r}", field="tolerance")
    return float(value)


class PointLaw(NamedTuple):
    """A contact's force law point by point: compiled kernels acting in parallel.

    F(delta, delta', delta'_0) = sum_j F_j(delta - shifts[j], delta', delta'_0; params[:, starts[j]:starts[j+1]])

    Attributes
    ----------
    kernels : LawTuple
        The kernels ``(delta, rate, approach_rate, params_row) -> (force [N], d force / d delta
        [N/m], d force / d rate [N s/m])`` (a compiled function each, or plain Python ones).
    shifts : ndarray (j,)
        Penetration [m] at which each kernel begins (0 for a law on its own).
    starts : ndarray (j + 1,) int64
        Each kernel's first column of ``params`` (and the end of the last).
    params : ndarray (m, p)
        The kernels' parameters at each of m points.
    """

    kernels: LawTuple
    shifts: np.ndarray
    starts: np.ndarray
    params: np.ndarray

    @classmethod
    def single(cls, kernel, params: np.ndarray) -> "PointLaw":
        """One kernel with its parameters (m, p) at m points."""
        params = np.ascontiguousarray(params, dtype=float)
        return cls(kernel_tuple((kernel,)), np.zeros(1), np.array([0, params.shape[1]], dtype=np.int64), params)

    def beside(self, other: "PointLaw", shift: float) -> "PointLaw":
        """This law in parallel with ``other`` acting on the penetration less ``shift`` [m]."""
        return PointLaw(kernel_tuple(tuple(self.kernels) + tuple(other.kernels)), np.concatenate([self.shifts, other.shifts + shift]),
                        np.concatenate([self.starts, other.starts[1:] + self.starts[-1]]),
                        np.ascontiguousarray(np.hstack([self.params, other.params])))

    @property
    def compiled(self) -> bool:
        """Whether every kernel is compiled (the solve then runs compiled whole)."""
        return all(is_compiled(k) for k in self.kernels)

    def at(self, i: int, delta: float, rate: float, approach_rate: float) -> tuple[float, float, float]:
        """(force [N], d/d delta [N/m], d/d rate [N s/m]) at point i's parameters."""
        f = point_force if self.compiled else point_force.py_func
        out = f(self.kernels, self.shifts, self.starts, float(delta), float(rate), float(approach_rate), self.params[i])
        return float(out[0]), float(out[1]), float(out[2])


class PointwiseLaw(ContactLaw):
    """A force law given point by point (see the module docstring).

    A subclass provides:

    1. ``law_force``: the compiled leaf kernel ``(delta, rate, approach_rate, params) ->
       (force, d_force_d_delta, d_force_d_rate)``, wrapped in ``staticmethod``;
    2. :meth:`params`: the (m, p) float64 parameters of m points from their effective masses;
    3. keyword-only parameters validated in ``__init__`` (:class:`~pounding.errors.InputError`
       naming the field).

    The engine asks :meth:`forces` for the end-of-step forces of the pressed points, given the
    contact state of the contact-law contract (an object with ``gap``, ``rate`` (m,), ``S_q``,
    ``S_v``, ``W`` (m, m), ``pair``, ``approach`` and ``share`` (m,): see the module docstring).
    """

    kind: ClassVar[str] = "force"
    #: the compiled point law (a subclass sets it, as staticmethod(kernel))
    law_force = None

    def __init__(self, *, restitution: float = 0.5, tolerance: float = 1e-4):
        super().__init__(restitution=restitution)
        self.tolerance = check_tolerance(tolerance)

    def params(self, m_eff: np.ndarray) -> np.ndarray:
        """Parameters (m, p) [float64] of the law at m points of effective masses ``m_eff`` (m,) [kg]."""
        raise NotImplementedError

    def point_law(self, m_eff: np.ndarray) -> PointLaw:
        """This law point by point at m points of effective masses ``m_eff`` (m,) [kg]: its kernel
        with :meth:`params`."""
        return PointLaw.single(self.law_force, self.params(np.asarray(m_eff, dtype=float)))

    def point_force(self, delta: float, rate: float, approach_rate: float, m_eff: float) -> tuple[float, float, float]:
        """(force [N], d force / d delta [N/m], d force / d rate [N s/m]) of one whole contact of
        effective mass ``m_eff`` [kg] at penetration ``delta`` [m], rate ``rate`` [m/s], begun at
        ``approach_rate`` [m/s]."""
        return self.point_law(np.array([float(m_eff)])).at(0, delta, rate, approach_rate)

    def forces(self, contact) -> np.ndarray:
        """End-of-step forces lambda (m,) [N] of the m pressed points of ``contact`` (the contact
        state: ``gap``, ``rate`` (m,) without contact forces, ``S_q``, ``S_v``, ``W`` (m, m),
        ``approach``, ``share`` (m,)), shared by the face rule and solved with the step
        (:func:`contact_forces`)."""
        return contact_forces(self.point_law(1.0 / np.diag(np.asarray(contact.W, dtype=float))), contact)

    def forces_solver(self, contact):
        """The solve of :meth:`forces` (:func:`point_solver`)."""
        return point_solver(self.point_law(1.0 / np.diag(np.asarray(contact.W, dtype=float))), contact)


def point_shares(contact) -> np.ndarray:
    """Share (m,) of the law each of the m points of ``contact`` carries (the face rule of the module
    docstring): its ``share``, fixed by the rest geometry, or 1 at every point of a state that
    carries none."""
    share = getattr(contact, "share", None)
    return np.ones(len(contact.gap)) if share is None else np.asarray(share, dtype=float)


def contact_forces(law: PointLaw, contact) -> np.ndarray:
    """End-of-step forces lambda (m,) [N] of the m pressed points of ``contact`` (the contact-law
    contract's state) under ``law``, shared by the face rule: :func:`point_solve` through
    :func:`point_solver`."""
    solve, args = point_solver(law, contact)
    return solve(args, np.ascontiguousarray(contact.gap, dtype=float), np.ascontiguousarray(contact.rate, dtype=float))


def point_solver(law: PointLaw, contact):
    """``(solve, args)`` of the contact-law contract (:meth:`~pounding.contact.base.ContactLaw.forces_solver`)
    for the points of ``contact`` under ``law``: :func:`point_solve` with the law's kernels and the
    points' history, shares and compliances; compiled where every kernel is, else the same function
    as Python (a third party's kernel written without the compiler)."""
    args = (_POINT_AT, (law.kernels, law.shifts, law.starts, law.params, np.ascontiguousarray(contact.approach, dtype=float)),
            point_shares(contact), np.ascontiguousarray(contact.S_q, dtype=float), np.ascontiguousarray(contact.S_v, dtype=float))
    return (point_solve if law.compiled else interpreted_point_solve), args


def interpreted_point_solve(args, gap, rate):
    """:func:`point_solve` with the compiler off (it and every compiled function it calls run as
    Python): the solve of a law with a kernel only Python knows."""
    with interpreted():
        return point_solve(args, gap, rate)


@njit
def point_solve(args, gap, rate):
    """The end-of-step forces lambda (m,) [N] of the points at the end gaps ``gap`` [m] and rates
    ``rate`` [m/s] (m,) without contact forces (the penetrations and their rates are their
    negatives): :func:`~pounding.contact.newton.solve_forces` with :func:`point_at`; ``args`` =
    (evaluator, (kernels, shifts, starts, params, approach), share, S_q, S_v) as :func:`point_solver`
    builds it."""
    evaluate, data, share, S_q, S_v = args
    return solve_forces(evaluate, data, -gap, -rate, share, S_q, S_v)[0]


@njit
def point_at(data, i, delta, rate):
    """(force [N], d/d delta [N/m], d/d rate [N s/m]) of point i at penetration ``delta`` [m] and
    rate ``rate`` [m/s]: the evaluator of :func:`~pounding.contact.newton.solve_forces` for a
    :class:`PointLaw`, ``data`` = (kernels, shifts, starts, params (m, p), approach (m,) [m/s])."""
    kernels, shifts, starts, params, approach = data
    return point_force(kernels, shifts, starts, delta, rate, approach[i], params[i])


#: the point laws' evaluator, as the solve takes it
_POINT_AT = kernel_tuple((point_at,))


@njit(borrowed=True)
def point_force(kernels, shifts, starts, delta, rate, approach_rate, params):
    """(force [N], d/d delta [N/m], d/d rate [N s/m]) of one point: the kernels in parallel, kernel
    j at the penetration ``delta - shifts[j]`` [m] with ``params[starts[j]:starts[j + 1]]``
    (:class:`PointLaw`)."""
    f, fd, fr = 0.0, 0.0, 0.0
    j = 0
    for kernel in literal_unroll(kernels):
        a, b, c = kernel(delta - shifts[j], rate, approach_rate, params[starts[j]:starts[j + 1]])
        f += a
        fd += b
        fr += c
        j += 1
    return f, fd, fr
