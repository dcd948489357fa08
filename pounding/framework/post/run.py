"""A run as a user calls it: the engine's analysis of a scene, then the checks of its result.

The driver (:class:`pounding.framework.engine.driver.Driver`) steps the model; this module
checks what comes back against physics before anyone reads it: the energy balance closes within
the scene's tolerance, every term that physics signs has its sign
(:func:`pounding.framework.post.energy_account.warn_if_energy_created`), and the response is finite.
"""

from __future__ import annotations

import numpy as np

from pounding.framework.engine.driver import Driver
from pounding.framework.engine.results import Result
from pounding.framework.model.scene import Scene
from pounding.framework.post.energy_account import energy_balance


def run(scene: Scene, *, progress=None, use_kernel: bool = True) -> Result:
    """Run the time-history analysis of a scene and return its :class:`Result`, checked by :func:`check`."""
    result = Driver(scene, progress=progress, use_kernel=use_kernel).run()
    check(scene, result)
    return result


def check(scene: Scene, result: Result) -> None:
    """The checks of a finished run, each a :class:`~pounding.errors.AnalysisWarning` naming what failed.

    The energy balance (of the buildings, or of the links' own account) misses by more than
    ``scene.analysis.energy_tolerance`` of the input; a contact rule that creates energy; a term
    of the account whose sign breaks physics; a given step too coarse for a force law's contact.
    Raises FloatingPointError when the response is not finite. States the impact-force model in
    ``result.info`` (summary.json)."""
    import warnings

    from pounding.errors import AnalysisWarning
    from pounding.framework.post.energy_account import warn_if_energy_created, warn_if_sign_broken
    from pounding.framework.post.response import impact_force_model

    eb = energy_balance(result)
    if abs(eb["relative_error"]) > eb["tolerance"]:
        warnings.warn(
            f"energy balance error {eb['relative_error']:.2e} of the input exceeds the tolerance "
            f"{eb['tolerance']:g} (summary.json: energy_balance)",
            AnalysisWarning,
            stacklevel=3,
        )
    links = eb.get("links")
    if links is not None and abs(links["relative_error"]) > eb["tolerance"]:
        warnings.warn(
            f"energy balance of the links {links['relative_error']:.2e} of the input exceeds the tolerance "
            f"{eb['tolerance']:g}: their work is not what they dissipated and store (summary.json: energy_balance.links)",
            AnalysisWarning,
            stacklevel=3,
        )
    if not np.all(np.isfinite(result.q)):
        raise FloatingPointError("the response is not finite: the integrator diverged (check dt against the shortest period)")
    result.info["impact_force"] = impact_force_model(scene.analysis.impact_force)  # stated in summary.json
    warn_if_contact_unresolved(result)  # a given step too coarse for a force law's contact
    warn_if_energy_created(result)  # a contact rule that creates energy is flagged
    warn_if_sign_broken(result)  # a term whose sign breaks physics is named


def warn_if_contact_unresolved(result: Result) -> str | None:
    """Warn (:class:`~pounding.errors.AnalysisWarning`) when the run's step spans its shortest contact
    (``result.info["contact_time"]``, :mod:`pounding.framework.engine.contact_step`) in fewer than
    :data:`~pounding.framework.engine.timestep.STEPS_PER_CONTACT` steps, with the numbers; returns the
    message (None: resolved, or no force law). Only a given ``[analysis] dt`` can: the default resolves it."""
    import warnings

    from pounding.errors import AnalysisWarning
    from pounding.framework.engine.timestep import STEPS_PER_CONTACT

    ct = result.info.get("contact_time") or {}
    steps = ct.get("steps_per_contact")
    if steps is None or steps >= STEPS_PER_CONTACT * (1.0 - 1e-9):
        return None
    a, fa, _, _, _ = result.pairs[ct["pair"]]
    other, fb = result.second_body(ct["pair"])
    message = (f"dt = {result.dt:g} s spans the shortest {ct['law']} contact ({ct['duration'] * 1e3:.3g} ms, "
               f"{result.names[a]} storey {fa + 1} against {other} {f'storey {fb}' if fb else '(a wall)'}) in {steps:.3g} steps; "
               f"the default step takes {STEPS_PER_CONTACT} per contact (peaks within 0.5 % of the converged run on the paper's "
               f"pair): dt <= {ct['resolving_dt']:.3g} s resolves it (leave [analysis] dt out for the default step)")
    warnings.warn(message, AnalysisWarning, stacklevel=4)
    return message
