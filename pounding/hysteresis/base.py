"""The link-law plugin contract (the hysteresis laws of yielding storey springs are link laws).

A *link* is a kinematic row over the modal coordinates: the relative displacement u [m] of two
bodies along a direction at a point (two floors of a building for a storey spring), as OpenSees'
zero-length element places a uniaxial material between two nodes. Its *law* maps the link's
deformation u, its rate v [m/s] and the law's committed state to the force r [N] it carries, with
its tangents, like OpenSees' ``UniaxialMaterial`` (``setTrialStrain(strain, strainRate)``,
``getStress``, ``getTangent``, ``getDampTangent``, ``commitState``, ``revertToLastCommit``). The
engine never asks which law a link has: it calls the law's compiled ``update``
(:mod:`pounding.framework.engine.links`). The plugin family keeps its name, ``pounding.hysteresis``.

Contract for an implementer
---------------------------
1. Subclass :class:`HysteresisLaw`; set ``name`` (the registered name) and
   ``n_params`` / ``n_state`` (lengths of the parameter and state vectors).
2. Take the law's own parameters keyword-only in ``__init__`` and check their
   valid range there, raising :class:`pounding.errors.InputError` with
   ``field`` = the parameter name (the element prefixes its key path).
3. :meth:`pack` returns the parameter vector of one link, shape
   (n_params,): ``params[0]`` the initial stiffness k0 [N/m], ``params[1]``
   the yield force Fy [N], ``params[2]`` the hardening ratio b [-] (post-yield
   over initial stiffness), then the law's own values.
4. ``update`` is a pure, numba-compiled function (``@njit``, no globals, no
   allocation)::

       force, tangent, damping = update(u, v, state, params, new_state, s)

   for link s: u [m] is its trial deformation and v [m/s] its rate (the engine
   passes the mean rate over the step, (u - state[s, 0]) / h); ``state``
   (ns, n_state) the committed states, never written; ``params`` (ns, n_params);
   ``new_state`` (ns, n_state) receives row s of the trial state. It returns the
   force [N], the tangent dr/du [N/m] and the damping tangent dr/dv [N s/m] of the
   trial state (0.0 for a rate-independent law; the engine's Newton uses
   dr/du + dr/dv / h). It depends on the committed state, u and v only, never on
   earlier trials (OpenSees' ``setTrialStrain`` from the last commit), so a driver
   may try any u any number of times (*trial*), then *commit* by copying
   ``new_state[s]`` into ``state[s]``, or *revert* by not copying it. The state
   lives in rows of arrays for all links, and the output in a buffer, so that
   the stepping loop neither allocates nor takes views per link and iteration (a
   view costs reference counting in numba: measured 100 ns per spring and step,
   15x the bilinear update itself). Declared ``@njit(borrowed=True)``
   (:func:`pounding.compiler.njit`), as the built-in laws are, it is compiled
   without numba's reference counts on its array arguments; numba refuses to
   compile it so if it allocates.
5. The first three state slots are common to every law: ``state[0]`` the
   deformation u [m], ``state[1]`` the force r [N], ``state[2]`` the energy the
   law has dissipated since the start [J] along its own path from the committed
   to the trial deformation (exact for the law's update). A virgin link has
   the zero state.
6. ``stored_energy(state, params) -> float`` [J] is the recoverable energy of
   a state (elastic plus hardening); the work done on the link is
   ``stored + dissipated``.
7. On the initial elastic branch the force must be computed as
   ``k0 * (u - s)`` with ``s`` exactly 0 before any yielding, so that the
   force's nonlinear part ``r - k0 u`` is exactly zero there: the stepping
   then reduces bit for bit to the elastic modal stepping.
8. A law whose physics fixes k0, Fy and b from its own parameters (an
   isolator: weight, radius, friction) returns them from :meth:`own_values`;
   the element then takes them from the law instead of its own keys.
9. :meth:`deformation_scale` is the deformation [m] at which the law's behaviour changes (the
   yield deformation Fy / k0 by default). It scales the stepping's Newton tolerance and the
   ductility outputs; a law without one (a linear spring, a damper) returns inf, and the
   engine takes the scale from the other links or the storey (:mod:`pounding.framework.engine.yielding`).
10. Optionally :meth:`opensees_material`: the law's OpenSees counterpart, the
   ``uniaxialMaterial`` a storey spring or a ``[[link]]`` with this law gets in the
   OpenSees peer of the tests and in ``pounding export opensees``
   (:mod:`pounding.peer`). Without it (the default raises NotImplementedError
   naming the law) a scene using the law cannot be exported.
   Optionally also :meth:`opensees_gap_material` and :meth:`opensees_gap_notes`: the law as a
   contact (the ``material`` contact law, :mod:`pounding.contact.material`: the law acting on the
   penetration, pushing only, keeping its state between touches) as an OpenSees gap material, and
   what that material computes differently. None (the default): OpenSees has no material that
   computes it, and the export leaves such a contact out.
11. Register the class under the entry-point group ``pounding.hysteresis`` (or
   pass the class itself): one module and one registration; the compiled
   stepping takes the law's ``update`` as an argument and is compiled once per
   run's set of laws, nothing else to write.
"""

from __future__ import annotations

from abc import ABC
from typing import Any, ClassVar

import numpy as np

#: Indices of the common state slots.
DEFORMATION, FORCE, DISSIPATED = 0, 1, 2
#: Indices of the common parameters.
STIFFNESS, YIELD_FORCE, HARDENING = 0, 1, 2


class HysteresisLaw(ABC):
    """Base class of every link law (hysteresis law; see the module docstring)."""

    name: ClassVar[str] = ""
    n_params: ClassVar[int] = 3
    n_state: ClassVar[int] = 3
    #: JSON schema of the law's own parameters (the keys of the element's
    #: ``hysteresis`` table besides ``name``).
    schema: ClassVar[dict[str, Any]] = {"type": "object", "additionalProperties": False, "properties": {}}
    #: the compiled update (force, tangent, damping tangent) and stored-energy functions (see the module docstring)
    update: ClassVar[Any]
    stored_energy: ClassVar[Any]

    def pack(self, stiffness: float, yield_force: float, hardening: float) -> np.ndarray:
        """Parameter vector (n_params,) of one spring: k0 [N/m], Fy [N], b [-], then the law's own."""
        return np.array([stiffness, yield_force, hardening], dtype=float)

    def own_values(self) -> tuple[float, float, float] | None:
        """(k0 [N/m], Fy [N], b [-]) when the law's own parameters fix them, else None (the default:
        the element gives them, e.g. storey_springs' ``stiffness``, ``yield_force``, ``hardening``)."""
        return None

    @staticmethod
    def deformation_scale(params: np.ndarray) -> float:
        """The deformation [m] at which the law's behaviour changes, from one link's parameter vector
        ``params`` (n_params,): the yield deformation Fy / k0 by default; inf for a law without one."""
        return float(params[YIELD_FORCE] / params[STIFFNESS])

    def opensees_material(self, ops, tag: int, k0: float, fy: float, b: float, *, tags, boucwen_tol: float) -> None:
        """Define the law's OpenSees counterpart as ``uniaxialMaterial`` ``tag`` with ``ops`` (the
        ``openseespy.opensees`` module, or a recorder of its commands), for a link of initial stiffness
        ``k0`` [N/m], yield force ``fy`` [N] and hardening ``b`` [-] (a storey spring's, or a
        ``[[link]]``'s from its parameter vector, :meth:`pack`'s first three values).

        ``tags()`` gives further free tags, for a material made of several (a ``Parallel`` of two);
        ``boucwen_tol`` [-] is the tolerance of OpenSees' ``BoucWen`` as a fraction of the yield
        displacement, for a law that uses it. The material's deformation is the link's u [m] and
        its stress the force [N].

        The default raises NotImplementedError: no OpenSees material for this law.
        """
        raise NotImplementedError(f"no OpenSees material for hysteresis law {self.name or type(self).__name__!r}")

    def opensees_gap_material(self, params: np.ndarray, share: float, clear: float) -> tuple | None:
        """The law's OpenSees counterpart as a contact: the ``uniaxialMaterial`` arguments after its tag
        (the material's name first) of a ``zeroLength`` contact element whose force is ``share`` [-]
        times this law's force at the penetration, the law pushing only and keeping its state
        between touches (:mod:`pounding.contact.material`); None (the default) when OpenSees has no
        material that computes that.

        ``params`` (n_params,) is the law's parameter vector (:meth:`pack`); ``share`` the share of one
        contact the element carries (1/2 at each end of a face); ``clear`` [m] the clear distance at
        rest. As for every gap material (:meth:`pounding.contact.base.ContactLaw.opensees_material`),
        the element's deformation is the separation's change, so the material takes ``-clear`` as the
        deformation at which contact begins and returns a negative (compressive) force [N].
        """
        return None

    def opensees_gap_notes(self, params: np.ndarray) -> list[str]:
        """What :meth:`opensees_gap_material` computes differently from the law as a contact, with the
        parameter vector ``params`` (n_params,), one sentence each; empty (the default) when nothing."""
        return []

    def describe(self) -> dict:
        """Name and parameters, as written to summary.json."""
        return {"name": self.name, **{k: v for k, v in vars(self).items() if not k.startswith("_")}}
