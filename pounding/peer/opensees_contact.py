"""Force contact laws as the OpenSees materials of the same name, in zero-length elements between floors.

OpenSees (since 3.1) models pounding with uniaxial gap materials in a ``zeroLength`` element
between the two bodies; three of them are laws of :mod:`pounding.contact`:

==============  =====================================================================
pounding law    OpenSees material (arguments after the tag)
==============  =====================================================================
``kelvin``      ``ViscoelasticGap K C gap``: K delta + C delta', which may pull (``tension = true``)
``hertz``       ``Hertzdamp Kh 0 gap n``: Hertzdamp with no damping is k_h delta^n exactly
``hertzdamp``   ``Hertzdamp Kh xiNorm gap n``
``jankowski``   ``JankowskiImpact Kh xi mEff gap 1.5``
``penalty``     ``ElasticPPGap k -1e30 gap 0 noDamage``: its spring only (no dashpot material)
==============  =====================================================================

Conventions. The element's deformation is u_j - u_i (node i on the building at -x, j on the
one at +x), negative when the slabs close; every gap material takes the clear distance as a
*negative* gap (the deformation at which contact begins) and returns a negative (compressive)
force. ``zeroLength`` passes the deformation rate to the material (delta' = -rate), and adds
stiffness-proportional Rayleigh damping only with ``-doRayleigh 1``, which these elements do not
have: the material is the whole contact, as a pounding law is.

Why ``Hertzdamp`` with no damping for ``hertz``: OpenSees has no elastic Hertz material, and the
other candidates are linear (``ElasticPPGap``, ``ElasticMultiLinear`` only approximates the power
law piecewise); ``Hertzdamp`` with xiNorm = 0 computes (Kh + 0) delta^n, the same formula.

The face rule. A pounding law gives the force of one contact (a pair of slabs at one storey);
where the slabs meet face to face its two ends share it, lambda_i = s_i F(delta_i, delta'_i;
m_eff,i) with s_i = 1/2 fixed by the rest geometry and m_eff,i = 1 / W_ii
(:mod:`pounding.contact.pointwise`, :mod:`pounding.framework.engine.face_shares`). Every law here is
homogeneous in that share: s F(delta, delta'; m) is the same law with the stiffness scaled by s
(and for Jankowski's damping, sqrt(s k_h ... s m) = s sqrt(k_h ... m), the effective mass too).
So each element gets the law's parameters at its point (``law.params(m_eff)``, the very numbers the
engine uses) with k (or k_h) and m_eff scaled by its share s = 1/2 (the two ends of a face). The
share is fixed in both, so the models are the same law whether both ends of a face press or one
alone.

What OpenSees computes differently (stated per material in :func:`material_notes`):

* ``Hertzdamp`` reads the impact velocity v_i from the first *trial* state in contact (the end
  of the first step that closes the gap, at every Newton iteration of it), where ``hertzdamp``
  uses the closing speed where the gap crossed zero: the two agree as the step shrinks, to first
  order. It pulls when 1 + xiNorm delta' / v_i < 0, where ``hertzdamp`` gives no force.
* ``ViscoelasticGap`` may pull: it is ``kelvin`` with ``tension = true``; the default
  ``tension = false`` clamps that pull and has no OpenSees material (the export says so).
* ``penalty`` with a restitution below 1 has a dashpot matrix shared by a face's points, which no
  uniaxial material holds: only its springs are exported.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

#: law name -> function (law, share, m_eff, clear) -> uniaxialMaterial arguments after the tag
_MATERIALS: dict[str, Callable] = {}


def _material(name: str):
    def register(fn):
        _MATERIALS[name] = fn
        return fn

    return register


@_material("kelvin")
def _viscoelastic_gap(law, share: float, m_eff: float, clear: float) -> tuple:
    k, c, _ = law.params(np.array([m_eff]))[0]
    return ("ViscoelasticGap", share * float(k), share * float(c), -clear)


@_material("hertz")
def _hertz(law, share: float, m_eff: float, clear: float) -> tuple:
    k, n = law.params(np.array([m_eff]))[0]
    return ("Hertzdamp", share * float(k), 0.0, -clear, float(n))


@_material("hertzdamp")
def _hertzdamp(law, share: float, m_eff: float, clear: float) -> tuple:
    k, n, xi = law.params(np.array([m_eff]))[0]
    return ("Hertzdamp", share * float(k), float(xi), -clear, float(n))


@_material("jankowski")
def _jankowski(law, share: float, m_eff: float, clear: float) -> tuple:
    k, xi, m = law.params(np.array([m_eff]))[0]
    return ("JankowskiImpact", share * float(k), float(xi), share * float(m), -clear, 1.5)


@_material("penalty")
def _penalty(law, share: float, m_eff: float, clear: float) -> tuple:
    # penalty puts a spring k_p at every point (a face of two points is 2 k_p), not a share of one
    return ("ElasticPPGap", float(law.stiffness), -1e30, -clear, 0.0, "noDamage")


def has_material(law) -> bool:
    """True when ``law`` (a contact law instance) has an OpenSees material here."""
    return getattr(law, "name", None) in _MATERIALS


def law_material(law) -> Callable[[float, float, float], tuple]:
    """The ``material(share, m_eff, clear)`` of :func:`pounding.peer.opensees.face_springs` for ``law``.

    It returns the ``uniaxialMaterial`` arguments after the tag of an element carrying ``share`` [-]
    of the contact at a point of effective mass ``m_eff`` [kg], the clear distance ``clear`` [m]
    (module docstring). Raises ``NotImplementedError`` for a law with no OpenSees material.
    """
    name = getattr(law, "name", None)
    if name not in _MATERIALS:
        raise NotImplementedError(f"contact law {name!r} has no OpenSees material (those with one: {', '.join(_MATERIALS)})")
    fn = _MATERIALS[name]
    return lambda share, m_eff, clear: fn(law, float(share), float(m_eff), float(clear))


def material_notes(law) -> list[str]:
    """What the OpenSees material of ``law`` does differently (one sentence each; empty when nothing)."""
    name = getattr(law, "name", None)
    if name == "kelvin" and not law.tension:
        return ["contact law 'kelvin' with tension = false never pulls, but its OpenSees material ViscoelasticGap "
                "does at the end of a contact (kelvin with tension = true): the script's contacts rebound with e "
                "where pounding's rebound faster"]
    if name == "hertzdamp":
        return ["contact law 'hertzdamp': OpenSees' Hertzdamp reads the impact velocity at the end of the first step "
                "in contact (pounding: where the gap closed), which agrees as dt shrinks, and pulls where "
                "1 + xi delta'/v_i < 0 (pounding gives no force there)"]
    if name == "penalty" and law.restitution < 1.0:
        return [f"contact law 'penalty': its dashpot (restitution {law.restitution:g}) has no counterpart in "
                "ElasticPPGap: the script's contact springs are elastic and lose no energy in impacts"]
    return []


def pair_law(scene, low, high):
    """The contact law instance of the slab pairs between buildings ``low`` and ``high`` of ``scene``: a
    ``[[contact]]`` rule between them, else ``[analysis] contact``."""
    from pounding.framework.model.registry import CONTACT_LAWS

    for rule in getattr(scene, "contacts", ()):
        if frozenset(rule.between) == frozenset((low.name, high.name)):
            return CONTACT_LAWS.get(rule.law)(**rule.params)
    an = scene.analysis
    return CONTACT_LAWS.get(an.contact)(**an.contact_params)


def run_law_pounding(ops, scene, dt: float, n_steps: int, *, out_of_plane: float = 1e-12, tol: float = 1e-12,
                     max_iter: int = 50):
    """The scene's pair pounding in OpenSees through the material of its contact law (module docstring).

    :func:`pounding.peer.opensees.run_face_pounding` with :func:`law_material` of the law between the
    scene's two buildings (the one at -x first, as the scene lists them); returns what it returns:
    (ux, forces, iterations, clear).
    """
    from pounding.peer.opensees import run_face_pounding

    low, high = scene.buildings
    material = law_material(pair_law(scene, low, high))
    return run_face_pounding(ops, scene, material, dt, n_steps, out_of_plane=out_of_plane, tol=tol, max_iter=max_iter)
