"""Plausibility checks: a valid scene whose numbers are unlikely for a real building.

Each check gives warnings, not errors: the number found, the usual range and
the likely cause (a unit slip, most often). Each has a name, by which it is
silenced (``[analysis] silence = ["mass_per_area"]`` or ``--silence NAME``).

* ``mass_per_area``: a slab's mass / plan area outside 150-4000 kg/m2 (a factor
  of two around the usual 300-2000 kg/m2 of floors with finishes and a share
  of live load). Tonnes entered as kg give ~1 kg/m2.
* ``period``: the first period per storey, T1 / N, outside 0.01-0.6 s (a factor
  of two around the usual 0.02-0.3 s: stiff walls to flexible frames; the code
  rule T ~ 0.1 N s sits inside).
* ``soft_storey``: a storey whose lateral stiffness, along x or y, is below 60 %
  of the storey above (ASCE 7-22 Table 12.3-2, extreme soft storey: 60 %).
  Storey stiffness is V_i / drift_i under forces proportional to mass x height
  (the equivalent lateral force pattern of a first mode), slabs kept from
  turning so that x and y are read apart.
* ``stiff_element``: an element whose lateral stiffness (the largest
  eigenvalue of its condensed matrix [N/m]) is above 1000x the median of the
  building's elements. Walls are 10-300x stiffer than frames; a section in mm
  or E in kPa is 1e3-1e12 off.
* ``isolation_damping``: a building whose isolators yield or slide (storey 1 an isolation layer of
  yielding storey springs) with Rayleigh or stiffness-proportional damping (per-mode ratios,
  ``type = "modal"``, are left to the user: they are the remedy). That damping is set on the
  initial model, with the isolators at their initial (stuck) stiffness, and keeps acting with it
  while they slide: a viscous force the bearings do not have, often a large share of the input
  energy (Ryan and Polanco 2008, J. Struct. Eng. 134(11); Charney 2008, J. Struct. Eng.
  134(4)). Usual practice damps the superstructure only.
* ``pga``: the ground motion's peak acceleration above 5 g. The largest ever recorded is about 4.4 g
  (Iwate-Miyagi 2008, vertical; horizontal peaks stay below 3 g); a value in cm/s2 (gal) typed as g,
  or a record in cm/s2 read as m/s2, gives hundreds of g.
* ``no_common_level``: two buildings with no slabs at a common level. Their
  slabs can only strike each other's facades between floors
  (:mod:`pounding.framework.model.facade`), a stronger idealisation than slab against
  slab (said once for the scene, naming every such pair). Unequal storey
  heights, or a slip in one of them, are the usual cause.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pounding.framework.model.stiffness_scale import STIFF_RATIO, describe, outliers


@dataclass(frozen=True)
class Check:
    """One plausibility check: its name, when it warns, and the likely cause (for the reference page)."""

    name: str
    condition: str
    cause: str


MASS_PER_AREA = (150.0, 4000.0)  # [kg/m2], usual 300-2000
PERIOD_PER_STOREY = (0.01, 0.6)  # [s], usual 0.02-0.3
SOFT_RATIO = 0.6  # storey stiffness / the storey above's
PGA_MAX = 5.0  # [g], above any recorded peak (about 4.4 g)

CHECKS = (
    Check("mass_per_area", f"a slab's mass per plan area is outside {MASS_PER_AREA[0]:g}-{MASS_PER_AREA[1]:g} kg/m2 (usual 300-2000)",
          "mass in tonnes instead of kg (1000x too small), or the mass of several floors on one slab"),
    Check("period", f"the first period per storey, T1 / storeys, is outside {PERIOD_PER_STOREY[0]:g}-{PERIOD_PER_STOREY[1]:g} s (usual 0.02-0.3 s)",
          "too short: mass too small (tonnes?) or stiffness too large (E or sections in the wrong units); too long: the reverse"),
    Check("soft_storey", f"a storey's lateral stiffness along x or y is below {100 * SOFT_RATIO:g} % of the storey above",
          "an element missing or undersized in that storey, a wrong storey height, or an element's `storeys` too small "
          "(not reported for an isolation layer: storey 1 of one-storey storey springs with elements standing on floor 1)"),
    Check("stiff_element", f"an element's lateral stiffness is above {STIFF_RATIO:g}x the median of its building's elements",
          "a section in mm instead of m, or E in kPa or MPa mixed with Pa"),
    Check("isolation_damping", "a building whose isolators yield or slide has Rayleigh or stiffness-proportional damping, set on "
          "its initial model (the isolators stuck at their initial stiffness)",
          "the damping of a fixed-base model kept for an isolated one: it acts on the sliding isolators as a viscous force "
          "they do not have; damp the superstructure's modes only (type = \"modal\", a small ratio on the isolated modes)"),
    Check("pga", f"the ground motion's peak acceleration is above {PGA_MAX:g} g (the largest recorded is about 4.4 g)",
          "a PGA in cm/s2 (gal) typed as g (`pga = 392` for 0.4 g), or a record in cm/s2 read as m/s2 (give its `units`)"),
    Check("no_common_level", "two buildings have no slabs at a common level: only slab-to-facade impacts between floors are checked between them",
          "unequal storey heights (intended: see *Slabs between a neighbour's floors* in docs/modelling.md), or a slip in a storey height"),
)
NAMES = tuple(c.name for c in CHECKS)


@dataclass(frozen=True)
class Finding:
    """One warning: the check's name and the message (with the number and the likely cause)."""

    check: str
    message: str

    def __str__(self) -> str:
        return f"{self.message} [silence with: {self.check}]"


def findings(scene, silence=()) -> list[Finding]:
    """Every plausibility warning of a scene, except the checks named in ``silence`` or ``scene.analysis.silence``."""
    from pounding.framework.model.assembly import assemble

    off = set(silence) | set(getattr(scene.analysis, "silence", ()))
    out: list[Finding] = []
    for b in scene.buildings:
        if "mass_per_area" not in off:
            out += _mass_per_area(b)
        if "period" not in off:
            out += _period(b, assemble(b))
        if "soft_storey" not in off:
            out += _soft_storeys(b)
        if "stiff_element" not in off:
            out += _stiff_elements(b)
        if "isolation_damping" not in off:
            out += _isolation_damping(b)
    if "no_common_level" not in off:
        out += _no_common_level(scene.buildings)
    if "pga" not in off:
        out += _pga(scene.ground_motion)
    return out


def _pga(motion) -> list[Finding]:
    from pounding.framework.model.units import G

    peak = float(getattr(motion, "pga", 0.0) or 0.0) / G  # [g] (a scene without a record: nothing to check)
    if not peak > PGA_MAX:
        return []
    return [Finding("pga", f"ground motion: peak acceleration {peak:.4g} g ({peak * G:.4g} m/s2) is beyond any recorded (about 4.4 g): "
                           f"a PGA in cm/s2 typed as g ({peak:.4g} cm/s2 = {peak / 100.0 / G:.3g} g)? a record in cm/s2 read as m/s2 "
                           f"({peak * G:.4g} cm/s2 = {peak / 100.0:.3g} g; give its `units`)?")]


def _no_common_level(buildings) -> list[Finding]:
    from pounding.framework.model.levels import unchecked_pairs

    pairs = unchecked_pairs(buildings)
    if not pairs:
        return []
    named = ", ".join(f"{a!r} and {b!r}" for a, b in pairs)
    return [Finding("no_common_level", f"no slabs at a common level between {named}: their slabs can only strike each other's "
                                       "columns and walls between floors (slab-to-facade impacts; unequal storey heights?)")]


def warn(scene, silence=()) -> list[Finding]:
    """Issue every finding as a :class:`~pounding.errors.PlausibilityWarning`; returns them."""
    import warnings

    from pounding.errors import PlausibilityWarning

    found = findings(scene, silence)
    for f in found:
        warnings.warn(str(f), PlausibilityWarning, stacklevel=2)
    return found


def _mass_per_area(b) -> list[Finding]:
    from pounding.contact.geometry import polygon_properties

    out = []
    for f, slab in enumerate(b.slabs):
        q = slab.mass / polygon_properties(slab.vertices)[0]
        if not MASS_PER_AREA[0] <= q <= MASS_PER_AREA[1]:
            cause = "mass in tonnes instead of kg?" if q < MASS_PER_AREA[0] else "the mass of several floors, or kg/m2 in place of kg?"
            out.append(Finding("mass_per_area", f"building {b.name!r} storey {f + 1}: mass per area {q:.4g} kg/m2 is far from the usual 300-2000 kg/m2 ({cause})"))
            break  # one per building: the same slip repeats on every storey
    return out


def _period(b, system) -> list[Finding]:
    T1 = float(system.periods[0])
    per = T1 / b.n_storeys
    if PERIOD_PER_STOREY[0] <= per <= PERIOD_PER_STOREY[1]:
        return []
    cause = ("mass too small (tonnes instead of kg?) or stiffness too large (E or sections in the wrong units?)" if per < PERIOD_PER_STOREY[0]
             else "mass too large or stiffness too small (E in MPa or GPa instead of Pa? sections in the wrong units?)")
    plural = "storey" if b.n_storeys == 1 else "storeys"
    return [Finding("period", f"building {b.name!r}: first period {T1:.4g} s for {b.n_storeys} {plural} ({per:.3g} s per storey) is far "
                              f"from the usual 0.02-0.3 s per storey: {cause}")]


def storey_stiffness(b, direction) -> np.ndarray:
    """Lateral stiffness of every storey along a plan direction [N/m], shape (N,).

    V_i / (d_i - d_{i-1}) under floor forces proportional to mass x elevation,
    with the slabs kept from turning (so the two plan directions are read apart).
    """
    from pounding.framework.model.assembly import stiffness

    n = b.n_storeys
    T = np.zeros((3 * n, n))
    for f in range(n):
        T[3 * f, f], T[3 * f + 1, f] = direction
    K = T.T @ stiffness(b) @ T
    F = np.array([s.mass for s in b.slabs]) * b.elevations
    d = np.linalg.solve(K, F)
    drift = np.diff(np.concatenate([[0.0], d]))
    shear = np.cumsum(F[::-1])[::-1]
    return shear / drift


def _soft_storeys(b) -> list[Finding]:
    from pounding.framework.model.isolation import isolation_layer

    out = []
    skip = {0} if isolation_layer(b) else set()  # storey 1 (0-based 0): an isolation layer is soft by design
    for axis, direction in (("x", (1.0, 0.0)), ("y", (0.0, 1.0))):
        try:
            k = storey_stiffness(b, direction)
        except np.linalg.LinAlgError:
            continue  # nothing resists this direction without torsion: the mechanism check speaks for it
        for f in range(b.n_storeys - 1):
            if f not in skip and 0 < k[f] < SOFT_RATIO * k[f + 1]:
                out.append(Finding("soft_storey", f"building {b.name!r} storey {f + 1} along {axis}: lateral stiffness {k[f] / 1e6:.4g} MN/m is "
                                                  f"{100 * k[f] / k[f + 1]:.0f} % of storey {f + 2}'s ({k[f + 1] / 1e6:.4g} MN/m): an element "
                                                  "missing or undersized there, or a wrong storey height?"))
    return out


def _slides(element) -> bool:
    """True when a line of springs yields or slides: its law has a finite yield deformation."""
    if not element.yields:
        return False
    law = element.law if isinstance(element.law, type) else type(element.law)
    return any(np.isfinite(law.deformation_scale(p)) for p in element.spring_parameters())


def _isolation_damping(b) -> list[Finding]:
    from pounding.framework.model.isolation import isolator_lines

    yielding = [i for i in isolator_lines(b) if _slides(b.elements[i])]
    ratios = np.atleast_1d(np.asarray(b.damping.ratio, dtype=float))
    # per-mode ratios are the remedy itself: the user chose which modes are damped
    if not yielding or b.damping.kind == "modal" or not np.any(ratios > 0.0):
        return []
    return [Finding("isolation_damping", f"building {b.name!r}: its isolators yield or slide (element[{', '.join(str(i) for i in yielding)}] "
                                         f"in storey 1), and its {b.damping.kind} damping (ratio {b.damping.ratio}) is set on the initial "
                                         "model, with the isolators at their initial stiffness: it keeps acting on them while they slide, "
                                         "a viscous force the bearings do not have. Damp the superstructure's modes only "
                                         "(type = \"modal\" with a small ratio on the modes the isolators carry), or silence this if intended")]


def _stiff_elements(b) -> list[Finding]:
    return [Finding("stiff_element", describe(b, i, k, med)) for i, k, med in outliers(b)]
