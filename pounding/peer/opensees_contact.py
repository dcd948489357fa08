"""Force contact laws as the OpenSees materials of the same name, in zero-length elements between floors.

OpenSees (since 3.1) models pounding with uniaxial gap materials in a ``zeroLength`` element
between the two bodies. Each contact law says which material is its counterpart
(:meth:`pounding.contact.base.ContactLaw.opensees_material`, None for a law OpenSees has no
material of) and what that material computes differently (``opensees_notes``); the peer asks
the law, never its name. The built-in laws with one:

==============  =====================================================================
pounding law    OpenSees material (arguments after the tag)
==============  =====================================================================
``kelvin``      ``ViscoelasticGap K C gap``: K delta + C delta', which may pull (``tension = true``)
``hertz``       ``Hertzdamp Kh 0 gap n``: Hertzdamp with no damping is k_h delta^n exactly
``hertzdamp``   ``Hertzdamp Kh xiNorm gap n``
``jankowski``   ``JankowskiImpact Kh xi mEff gap 1.5``
``penalty``     ``ElasticPPGap k -1e30 gap 0 noDamage``: its spring only (no dashpot material)
``material``    its link law's gap material (``HysteresisLaw.opensees_gap_material``):
                ``ElasticPPGap k -1e30 gap 0 noDamage`` for ``elastic``,
                ``ElasticPPGap k0 -Fy gap b damage`` for ``bilinear``; none for the others
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

What OpenSees computes differently (stated by each law's ``opensees_notes``):

* ``Hertzdamp`` reads the impact velocity v_i from the first *trial* state in contact (the end
  of the first step that closes the gap, at every Newton iteration of it), where ``hertzdamp``
  uses the closing speed where the gap crossed zero: the two agree as the step shrinks, to first
  order. It pulls when 1 + xiNorm delta' / v_i < 0, where ``hertzdamp`` gives no force.
* ``ViscoelasticGap`` may pull: it is ``kelvin`` with ``tension = true``. The default
  ``tension = false`` clamps that pull, which the material does not: it is exported with
  ``ViscoelasticGap`` all the same, and the script says its contacts rebound with e where
  pounding's rebound faster.
* ``penalty`` with a restitution below 1 has a dashpot matrix shared by a face's points, which no
  uniaxial material holds: only its springs are exported.
* ``material`` with ``bilinear`` (kinematic hardening b > 0) reaches its lower bound while it still
  pushes once a penetration has passed (1 + 1/b) Fy / k0, and then parts at a smaller plastic set;
  ``ElasticPPGap`` unloads elastically to its set whatever the penetration. Below that they are the
  same law: elastic from the set to the line Fy + b k0 (delta - Fy / k0), the set moved on commit to
  where the force unloads to zero and kept while apart (``damage``). The kinematic bounds scale with
  (k0, Fy), so the share scales both.
"""

from __future__ import annotations

from typing import Callable

#: the laws the export writes a contact material for, as its notes name them
WITH_MATERIAL = "kelvin, hertz, hertzdamp, jankowski, penalty, or material with an elastic or bilinear link law"


def has_material(law) -> bool:
    """True when ``law`` (a contact law instance) has an OpenSees material: it gives one
    (:meth:`~pounding.contact.base.ContactLaw.opensees_material`, asked for a whole contact at a point
    of 1 kg touching at rest; a law without one gives None whatever it is asked)."""
    return law.opensees_material(1.0, 1.0, 0.0) is not None


def law_material(law) -> Callable[[float, float, float], tuple]:
    """The ``material(share, m_eff, clear)`` of :func:`pounding.peer.opensees.face_springs` for ``law``.

    It returns the ``uniaxialMaterial`` arguments after the tag of an element carrying ``share`` [-]
    of the contact at a point of effective mass ``m_eff`` [kg], the clear distance ``clear`` [m]
    (module docstring): the law's own
    :meth:`~pounding.contact.base.ContactLaw.opensees_material`. Raises ``NotImplementedError`` for
    a law with no OpenSees material.
    """
    from pounding.contact.rules import law_name

    if not has_material(law):
        raise NotImplementedError(f"contact law {law_name(law)!r} has no OpenSees material "
                                  "(its class gives none: ContactLaw.opensees_material)")
    return lambda share, m_eff, clear: law.opensees_material(float(share), float(m_eff), float(clear))


def pair_law(scene, low, high):
    """The contact law instance of the slab pairs between buildings ``low`` and ``high`` of ``scene``, as a
    run of the scene gives them (:func:`pounding.contact.rules.scene_laws`: a ``[[contact]]`` rule
    between them, else ``[analysis] contact``; with contact off, that law everywhere).

    The pairs are the common storeys' (storey f of one with storey f of the other), the contact
    elements' of :func:`pounding.peer.opensees.face_springs`. Raises ValueError when they do not all
    take one law (a bumper in some of them): the peer writes one material per pair of buildings.
    """
    from pounding.contact.rules import law_name, scene_laws

    names = [b.name for b in scene.buildings]
    a, b = names.index(low.name), names.index(high.name)
    pairs = [(a, f, b, f, 0.0) for f in range(min(low.n_storeys, high.n_storeys))]
    laws, which = scene_laws(scene, pairs)
    taken = sorted({int(j) for j in which})
    if len(taken) > 1:
        raise ValueError(f"the storeys between {low.name!r} and {high.name!r} take different contact laws "
                         f"({', '.join(repr(law_name(laws[j])) for j in taken)}: a bumper in some of them), and the "
                         "OpenSees model writes one material for the pair")
    return laws[taken[0]]


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
