"""Any link law as a contact law (``material``): OpenSees' zero-length contact element with a
uniaxial material, in series with a gap that carries no tension.

The link laws (the ``pounding.hysteresis`` family: ``bilinear``, ``bouc_wen``, ``elastic``,
``viscous``, ``maxwell``, ``kelvin``, ``friction_pendulum``, a plugin's) are pounding's uniaxial
materials: the storey springs and the ``[[link]]`` tables step them. ``material`` puts one at every
contact point of the pairs it serves, the law named by a table ``material`` as a ``[[link]]``'s ``law`` is::

    [analysis]
    contact = { name = "material", material = { name = "bilinear", stiffness = 2.0e9, yield_force = 4.0e6, hardening = 0.02 } }

At each point the material's deformation u [m] is the penetration delta (zero at the first touch)
and its rate the mean over the step, (u - u_c) / h with u_c its committed deformation, as the links
are stepped. The point carries

    lambda_i = share_i r(u_i, u'_i; state_i)    while r > 0 (the material pushes),

and nothing where the material would pull: the surfaces part. The material then unloads within the
step to where it carries no force (an elastic spring to zero, a bilinear one to its plastic set, a
dashpot stays where it was, a spring beside a dashpot relaxes by one implicit step) and keeps that
state while apart, so the surfaces touch again where the penetration reaches that deformation (a
plastic set is a permanent gap). It does not relax further while apart: exact for a
rate-independent law and for a dashpot, while a law with a spring and a dashpot (``kelvin``, side
by side; ``maxwell``, in series) keeps what it had not recovered when the surfaces parted. ``share_i`` is the face rule's
(:mod:`pounding.contact.pointwise`): 1/2 at each end of a face, so a face pressed flat carries one
material's force.

Every point keeps its material's state (``ContactState.point``); each call of :meth:`forces` is a
trial from the committed states, and :meth:`commit` moves them with the step the engine accepted
(:meth:`~pounding.contact.base.ContactLaw.commit`). The step's forces are solved with it by
Newton's method on lambda - share r(delta_0 - S_q lambda, ...) with the material's tangent
dr/du + (dr/du') / h (the links' Newton), backtracking on the residual's norm: one compiled function,
:func:`material_forces`, that takes the law's update as a plugin (compiled once per law), or runs as
Python around a law's update written without the compiler.

OpenSees: each link law says what its OpenSees gap material is
(:meth:`pounding.hysteresis.base.HysteresisLaw.opensees_gap_material`), and :meth:`MaterialContact.opensees_material`
asks it: ``ElasticPPGap`` for ``elastic`` (an elastic gap) and for ``bilinear`` (with ``damage``:
its gap keeps the plastic set). OpenSees has no gap material for the others, which the export
leaves out: ``bouc_wen``, ``maxwell`` and ``friction_pendulum`` exist only without a gap, and
``ViscoelasticGap`` (a dashpot, or a spring beside one, behind a gap) pulls as the surfaces part.

Glossary: delta the penetration [m] (> 0 where the slabs overlap), u [m], u' [m/s], r [N],
h the step [s], share [-].
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np

from pounding.compiler import interpreted, is_compiled, njit
from pounding.compiler.unroll import kernel_tuple, literal_unroll, unrolled_in
from pounding.contact.base import ContactLaw, ContactState
from pounding.contact.newton import NEWTON_ITERATIONS, solve_forces
from pounding.contact.pointwise import check_tolerance
from pounding.errors import InputError

unrolled_in(globals())  # this module's literal_unroll: numba's once numba is set up


class MaterialContact(ContactLaw):
    """A link law at every contact point, whose surfaces part rather than pull (module docstring).

    Parameters
    ----------
    material : table
        The link law, ``{ name = ..., ... }`` as a ``[[link]]``'s ``law``: a law that sets its own
        stiffness (``elastic``, ``viscous``, ``maxwell``, ``kelvin``, ``friction_pendulum``) with its own
        parameters; any other (``bilinear``, ``bouc_wen``, a plugin's) with ``stiffness`` [N/m],
        ``yield_force`` [N] and ``hardening`` [-] beside its own.
    restitution : float
        Accepted (every law takes it) and unused: the loss follows from the material.
    tolerance : float
        Contact length tolerance [m]: a pair within it is watched.
    """

    name: ClassVar[str] = "material"
    kind: ClassVar[str] = "force"
    keeps_state: ClassVar[bool] = True
    #: the scene table's schema (the scene reference is generated from it)
    schema: ClassVar[dict] = {
        "type": "object",
        "description": "A link law (a uniaxial material: `bilinear`, `bouc_wen`, `elastic`, `viscous`, `maxwell`, `kelvin`, "
                       "`friction_pendulum`, a plugin's) at every contact point, pushing only: where it would pull the "
                       "surfaces part, and it keeps its state (a plastic set) for the next touch. OpenSees' zero-length "
                       "contact element with a uniaxial material.",
        "properties": {
            "material": {"type": "object", "description": "The link law at each contact point, `{ name = ..., ... }` as a "
                         "[[link]]'s `law`: stiffness [N/m], yield_force [N] and hardening [-] beside the law's own parameters, "
                         "or only its own for a law that sets them (elastic, viscous, maxwell, kelvin, friction_pendulum).",
                         "examples": [{"name": "bilinear", "stiffness": 2.0e9, "yield_force": 4.0e6, "hardening": 0.02}]},
            "restitution": {"type": "number", "units": "-", "default": 1.0,
                            "description": "Accepted (as by every contact law) and unused: the loss follows from the material."},
            "tolerance": {"type": "number", "units": "m", "default": 1e-4,
                          "description": "Contact length tolerance [m] (a pair within it is watched)."},
        },
        "required": ["material"],
    }

    def __init__(self, *, material: Any = None, restitution: float = 1.0, tolerance: float = 1e-4):
        from pounding.framework.model.law_tables import link_law

        super().__init__(restitution=restitution)
        if not isinstance(material, dict) or "name" not in material:
            raise InputError("expected the link law at each contact point as a table { name = ..., ... } (as a [[link]]'s law), "
                             f"got {material!r}", field="material")
        self.material, self.values = link_law(material, "material")
        self._laws = kernel_tuple((self.material.update,))  # the law's update, as the compiled solve takes it
        self.tolerance = check_tolerance(tolerance)
        self._spec = dict(material)
        #: by point (pair, striking slab, vertex): its material's committed state (n_state,)
        self._state: dict[tuple, np.ndarray] = {}

    def describe(self) -> dict:
        """Name, the material's table and the tolerance, as written to summary.json."""
        return {"name": self.name, "material": dict(self._spec), "restitution": self.restitution, "tolerance": self.tolerance}

    def contact_duration(self, m_eff: float, approach_speed: float) -> float:
        """Duration [s] of a linear spring and dashpot's contact of effective mass ``m_eff`` [kg]
        (:func:`~pounding.contact.kelvin.kelvin_contact_duration`, compression only), with the
        material's initial stiffness k0 and the damping its tangent gives at the first touch at
        ``approach_speed`` [m/s]: half the period pi sqrt(m_eff / k0) for a rate-independent material
        (a yielding one's contact lasts longer, its elastic phases no shorter), shorter with a
        dashpot; inf for a material without a stiffness (a dashpot alone)."""
        from pounding.contact.kelvin import kelvin_contact_duration

        k0 = float(self.values[0])
        if not (k0 > 0.0 and math.isfinite(k0) and m_eff > 0.0):
            return math.inf
        n = self.material.n_state
        state, params, new = np.zeros((1, n)), self.values[None, :].copy(), np.empty((1, n))
        u = 1e-9 * max(float(approach_speed), 1e-12) * math.sqrt(m_eff / k0)  # just after the touch
        _, _, c = self.material.update(u, float(approach_speed), state, params, new, 0)
        return kelvin_contact_duration(k0, m_eff, max(float(c), 0.0) / (2.0 * math.sqrt(k0 * m_eff)), False)

    def opensees_material(self, share: float, m_eff: float, clear: float) -> tuple | None:
        """The material's OpenSees gap material for an element carrying ``share`` [-] of a contact,
        the slabs ``clear`` [m] apart at rest (:meth:`~pounding.hysteresis.base.HysteresisLaw.opensees_gap_material`
        with the law's parameter vector, the one the engine steps), or None where OpenSees has none;
        ``m_eff`` [kg] is not read (no link law's parameters depend on the pair's mass). See
        :meth:`ContactLaw.opensees_material`."""
        return self.material.opensees_gap_material(self.values, float(share), float(clear))

    def opensees_notes(self) -> list[str]:
        """What the material's OpenSees gap material computes differently
        (:meth:`~pounding.hysteresis.base.HysteresisLaw.opensees_gap_notes`), naming this law."""
        return [f"contact law {self.name!r}: {note}" for note in self.material.opensees_gap_notes(self.values)]

    # ---------------------------------------------------------------- the points' committed states
    def _committed(self, contact: ContactState) -> tuple[list[tuple], np.ndarray, np.ndarray]:
        """(keys, committed states (m, n_state), parameters (m, n_params)) of the points of ``contact``
        (a point never committed: the virgin state)."""
        if contact.point is None:
            raise ValueError("the material contact law keeps a state per point: the contact state must identify its points")
        keys = [tuple(int(x) for x in p) for p in contact.point]
        m = len(keys)
        state = np.zeros((m, self.material.n_state))
        for j, key in enumerate(keys):
            row = self._state.get(key)
            if row is not None:
                state[j] = row
        params = np.ascontiguousarray(np.broadcast_to(self.values, (m, len(self.values))))
        return keys, state, params

    def _run(self, fn, *args):
        """``fn(*args)``, compiled where the law's update is, else the same function as Python (a third
        party's law written without the compiler)."""
        if is_compiled(self.material.update):
            return fn(*args)
        with interpreted():
            return fn(*args)

    def _force_at(self, u: float, h: float, state, params, new, j: int) -> float:
        """Point j's material force [N] at deformation u [m] (:func:`material_at`); ``new[j]`` its trial state."""
        return float(self._run(material_at, self._laws, float(u), h, state, params, new, j)[0])

    # ---------------------------------------------------------------- the contract
    def forces(self, contact: ContactState) -> np.ndarray:
        """End-of-step forces (m,) [N] of the points of ``contact`` (module docstring); a trial: the
        committed states are read, never written."""
        _, state, params = self._committed(contact)
        return self._solve(contact, state, params)

    def _solve(self, c: ContactState, state, params) -> np.ndarray:
        """:func:`material_forces` of the points of ``c`` from their committed states: compiled where the
        law's update is, else the same function as Python (a third party's law written without the compiler)."""
        m = len(c.gap)
        lam, settled = self._run(material_forces, self._laws, -np.asarray(c.gap, dtype=float),
                                 np.ones(m) if c.share is None else np.asarray(c.share, dtype=float),
                                 np.ascontiguousarray(c.S_q, dtype=float), float(c.dt), state, params)
        if not settled:
            import warnings

            from pounding.errors import AnalysisWarning

            warnings.warn(f"the material contact's forces did not settle in {NEWTON_ITERATIONS} Newton iterations at "
                          f"t = {c.t:.6g} s (a smaller dt resolves the contact)", AnalysisWarning, stacklevel=3)
        return np.maximum(lam, 0.0)

    def commit(self, contact: ContactState, forces: np.ndarray) -> None:
        """Move the points' materials to the accepted step's end: a point whose material pushes there
        commits its trial state at its end penetration; one whose material does not has parted, and
        so has every point this law kept that is no longer pressed: its material unloads within the
        step to where it carries no force (:meth:`_unloaded`; a point apart, from zero penetration)."""
        keys, state, params = self._committed(contact)
        h = float(contact.dt)
        delta = -(np.asarray(contact.gap, dtype=float) + np.asarray(contact.S_q, dtype=float) @ forces)
        new = np.empty_like(state)
        for j, key in enumerate(keys):
            if not self._force_at(delta[j], h, state, params, new, j) > 0.0:
                self._unloaded(float(delta[j]), h, state, params, new, j)
            self._state[key] = new[j].copy()
        pressed = set(keys)
        for key, row in self._state.items():  # the points that let go: unloaded once, then kept as they are
            if key not in pressed and row[1] > 0.0:
                one, new = row[None, :].copy(), np.empty((1, row.shape[0]))
                self._unloaded(min(0.0, float(row[0])), h, one, self.values[None, :].copy(), new, 0)
                self._state[key] = new[0].copy()

    def _unloaded(self, u_end: float, h: float, state, params, new, j: int) -> float:
        """The deformation u [m] at which point j's material, from its committed state, carries no
        force at the end of a step of h [s] (its rate the mean over the step), ``new[j]`` its state
        there: a root of r between ``u_end`` (where it does not push) and its committed deformation
        (Brent's method; r rises with u for a passive material). An elastic spring unloads to zero
        deformation, a bilinear one to its plastic set, a dashpot stays where it was, a spring beside
        a dashpot relaxes by one implicit step. A material that carries no force at its committed
        deformation (it parted in an earlier step) stays as committed."""
        from scipy.optimize import brentq

        u_c = float(state[j, 0])

        def force(u):
            return self._force_at(u, h, state, params, new, j)

        if not force(u_c) > 0.0:  # unloaded already (parted in an earlier step): it stays as committed
            new[j] = state[j]
            return u_c
        if force(u_end) <= 0.0:
            u = brentq(force, min(u_end, u_c), max(u_end, u_c), xtol=1e-15 * max(abs(u_c), abs(u_end), 1e-300), rtol=4 * np.finfo(float).eps)
        else:  # (it pushes at the step's end: a force of zero to the solve's tolerance)
            u = u_end
        force(u)  # (leaves new[j] at u)
        return u


@njit
def material_forces(laws, u0, share, S_q, h, state, params):
    """(lambda (m,) [N], settled) of m points, each with the link law of ``laws`` (a
    :class:`~pounding.compiler.unroll.LawTuple` of its one ``update``) from its committed state:
    the end-of-step forces, and whether the Newton iteration met its tolerance.

    Solves ``lambda_i = share_i r_i`` where the material pushes (r_i > 0), else ``lambda_i = 0``, with
    ``u = u0 - S_q lambda`` the end deformations [m] (u0 (m,) those without contact forces), each at its
    mean rate over the step of h [s] from its committed deformation ``state[i, 0]``:
    :func:`~pounding.contact.newton.solve_forces` with :func:`material_point`, whose tangent is
    dr/du + (dr/du') / h. ``state`` (m, n_state) and ``params`` (m, n_params) are the points' rows of the
    link-law contract (:mod:`pounding.hysteresis.base`); ``share`` (m,) the face rule's; ``S_q`` (m, m) [m/N]."""
    m = u0.shape[0]
    # the rate is the material's own (its mean over the step): the solve's rate is not read, and its
    # compliance is S_q's shape only
    return solve_forces(_MATERIAL_POINT, (laws, h, state, params, np.empty(state.shape)), u0, np.zeros(m), share, S_q, S_q)


@njit
def material_point(data, i, u, rate):
    """(r [N], dr/du + (dr/du') / h [N/m], 0) of point i's material where it pushes (r > 0), else zeros
    (the surfaces part): the evaluator of :func:`~pounding.contact.newton.solve_forces` for the
    material contact, ``data`` = (laws, h [s], state, params, new) as :func:`material_at` takes them;
    ``rate`` is not read (the material's rate is its mean over the step, from u)."""
    laws, h, state, params, new = data
    f, tangent = material_at(laws, u, h, state, params, new, i)
    if f > 0.0:
        return f, tangent, 0.0
    return 0.0, 0.0, 0.0


#: the material contact's evaluator, as the solve takes it
_MATERIAL_POINT = kernel_tuple((material_point,))


@njit
def material_at(laws, u, h, state, params, new, i):
    """(r [N], dr/du + (dr/du') / h [N/m]) of point i's material (the link law of ``laws``, from its
    committed state ``state[i]``) at deformation u [m] and its mean rate over the step of h [s],
    (u - state[i, 0]) / h; ``new[i]`` receives its trial state."""
    f, ft, fd = 0.0, 0.0, 0.0
    for law in literal_unroll(laws):  # (one law)
        f, ft, fd = law(u, (u - state[i, 0]) / h, state, params, new, i)
    return f, ft + fd / h
