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
    """Run the time-history analysis of a scene and return its :class:`Result`.

    Warns (:class:`~pounding.errors.AnalysisWarning`) when the energy balance
    misses by more than ``scene.analysis.energy_tolerance`` of the input.
    """
    import warnings

    from pounding.errors import AnalysisWarning

    result = Driver(scene, progress=progress, use_kernel=use_kernel).run()
    eb = energy_balance(result)
    if abs(eb["relative_error"]) > eb["tolerance"]:
        warnings.warn(
            f"energy balance error {eb['relative_error']:.2e} of the input exceeds the tolerance "
            f"{eb['tolerance']:g} (summary.json: energy_balance)",
            AnalysisWarning,
            stacklevel=2,
        )
    if not np.all(np.isfinite(result.q)):
        raise FloatingPointError("the response is not finite: the integrator diverged (check dt against the shortest period)")
    from pounding.framework.post.energy_account import warn_if_energy_created, warn_if_sign_broken
    from pounding.framework.post.response import impact_force_model

    result.info["impact_force"] = impact_force_model(scene.analysis.impact_force)  # stated in summary.json
    warn_if_energy_created(result)  # a contact rule that creates energy is flagged
    warn_if_sign_broken(result)  # a term whose sign breaks physics is named
    return result
