"""The energy audit: ground-motion work = kinetic + strain + damping + impact losses (+ contact-force work).

Work integrals use the trapezoidal rule on step ends, which is the exact discrete
identity of the average-acceleration rule, and closed-form integrals on the exact
integrator's own trajectory; so for those two schemes the balance closes to rounding
even through impacts (impulses book their loss exactly, (1 - k^2) b^2 / 2a).
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import pytest

from pounding.errors import AnalysisWarning
from pounding.framework.post.run import run
from pounding.io.scene import load_scene
from pounding.framework.post.energy_account import energy_balance

PAPER = Path(__file__).resolve().parents[1] / "examples" / "paper" / "pair_gap_0.03.toml"


@pytest.fixture(scope="module")
def scene():
    return load_scene(PAPER).with_analysis(duration=8.0)


def test_average_acceleration_balance_closes_through_impacts(scene):
    """Newmark average acceleration, accelerations from equilibrium after impact: 1e-10 of the input
    (measured 1e-14 over the whole record with 80 impacts)."""
    r = run(scene.with_analysis(integrator="newmark", integrator_params={}, contact_params={"restitution": 0.5, "after_impact": "equilibrium"}))
    assert r.n_impacts > 10
    assert abs(energy_balance(r)["relative_error"]) < 1e-10


@pytest.mark.parametrize("locate", ["halving", "root"])
def test_exact_integrator_balance_closes_through_impacts(scene, locate):
    """The exact integrator with closed-form work integrals: 1e-8 of the input (measured 3e-15 and
    2e-14 on the paper pair; 7e-11 with the 4-point Gauss rule it had before)."""
    r = run(scene.with_analysis(integrator="exact", integrator_params={}, contact_params={"restitution": 0.7, "locate": locate}))
    assert r.n_impacts > 10
    assert abs(energy_balance(r)["relative_error"]) < 1e-8


def test_perfectly_elastic_impacts_lose_nothing(scene):
    """k = 1: the impact losses are zero to rounding and the balance still closes."""
    r = run(scene.with_analysis(integrator="newmark", integrator_params={}, contact_params={"restitution": 1.0, "after_impact": "equilibrium"}))
    eb = energy_balance(r)
    assert r.n_impacts > 0
    assert abs(eb["impact_loss"]) < 1e-9 * eb["input"]
    assert abs(eb["relative_error"]) < 1e-10


def test_hht_dissipation_shows_in_the_balance_and_a_tight_tolerance_warns(scene):
    """HHT (alpha = -0.1) damps high modes numerically: input exceeds what is accounted for,
    and a tolerance below that (1e-6) triggers the warning and ok = false in summary.json."""
    tight = scene.with_analysis(integrator="hht", integrator_params={"alpha": -0.1}, contact="none", contact_params={}, energy_tolerance=1e-6)
    with pytest.warns(AnalysisWarning, match="energy balance"):
        r = run(tight)
    eb = energy_balance(r)
    assert eb["relative_error"] > 1e-6 and eb["ok"] is False


def test_keeping_accelerations_after_impact_is_visible_in_the_balance(scene):
    """The paper keeps the pre-impact accelerations: inconsistent with equilibrium, they create
    energy (negative balance error, measured ~1e-2 on this case) where equilibrium gives 1e-14."""
    keep = run(scene.with_analysis(integrator="newmark", integrator_params={}, contact_params={"restitution": 0.5, "after_impact": "keep"}))
    assert energy_balance(keep)["relative_error"] < -1e-4


def test_no_warning_within_tolerance(scene):
    with warnings.catch_warnings():
        warnings.simplefilter("error", AnalysisWarning)
        run(scene.with_analysis(integrator="newmark", integrator_params={}, contact="none", contact_params={}))


def test_summary_reports_every_term(tmp_path, scene):
    from pounding.io.results import write_results

    r = run(scene.with_analysis(duration=3.0))
    write_results(r, tmp_path / "o")
    eb = json.loads((tmp_path / "o" / "summary.json").read_text())["energy_balance"]
    assert set(eb) >= {"input", "kinetic_plus_strain", "damping", "impact_loss", "contact_force_work", "error", "relative_error", "tolerance", "ok"}
