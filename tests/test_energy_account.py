"""Each building's energy account balances on its own; the pair's is their sum.

For one building, its equation of motion times its velocity, integrated over the run:
input + contact-force work + impact work = kinetic + strain + damping, where the impact
work is the jump of its kinetic energy at the impulses it received. Energy passes
between the buildings only through impacts and contact forces, so summing the two
accounts gives the pair's, whose impact work is minus the impacts' losses. Average
acceleration's trapezoidal work identity is exact for its own trajectory, and the
accelerations reset to equilibrium after an impact keep it so: each account then closes
to rounding (pounding.framework.post.energy_account).
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

from pounding.errors import AnalysisWarning
from pounding.framework.post.run import run
from pounding.framework.post.energy_account import building_balances, energy_creating_rule
from pounding.io.scene import load_scene
from tests.scenes_for_tests import scene as build_scene
from tests.scenes_for_tests import side_by_side
from pounding.framework.post.energy_account import energy_balance

PAPER = Path(__file__).resolve().parents[1] / "examples" / "paper" / "pair_gap_0.03.toml"
EQUILIBRIUM = {"restitution": 0.5, "after_impact": "equilibrium"}


def _scenes():
    """The paper pair (whole record, 77 impacts, held episodes) and a pair of box buildings
    shaken at 30 degrees that pound at several storeys, with plastic impacts (k = 0), so that
    pairs are held in sustained contact and the contact forces do work on each building."""
    paper = load_scene(PAPER).with_analysis(integrator="newmark", integrator_params={}, contact_params=EQUILIBRIUM)
    data = side_by_side(0.002, storeys=(3, 5), duration=4.0, integrator="newmark", restitution=0.0)
    data["ground_motion"]["angle"] = 30.0
    data["analysis"]["contact"] = {"name": "impulse", "after_impact": "equilibrium"}
    return {"paper": paper, "plastic_30deg": build_scene(data)}


@pytest.fixture(scope="module", params=["paper", "plastic_30deg"])
def case(request):
    result = run(_scenes()[request.param])
    return request.param, result, building_balances(result)


def test_every_building_balances_on_its_own(case):
    """Average acceleration, equilibrium after impact: each building's account closes to 1e-12
    of its input. Rounding: each of the O(1e4) steps and O(1e2) impact instants adds a few
    ulps of the energies in play (<= the input), so ~1e4 x 1e-16 = 1e-12 at most; measured
    2e-15 to 2.5e-14. (Without the impact work in it, a building's account misses by the energy
    the impacts passed to or took from it: 7 % and 11 % of the input on the paper pair, 29 %
    for the left building of the plastic pair.)"""
    name, result, bal = case
    assert result.n_impacts > 10
    for b, e in bal.items():
        assert abs(e["relative_error"]) <= 1e-12, (name, b, e)
        assert abs(e["impacts"]) > 1e-3 * e["input"], "the impacts pass energy between the buildings"


def test_the_buildings_accounts_sum_to_the_pairs(case):
    """Sum over the buildings of the impact work = - the impacts' losses (each impact's two
    impulses together dissipate exactly its loss); the sum of the buildings' errors = the pair's
    error. Both to rounding of the largest term: 1e-12 of the input."""
    name, result, bal = case
    pair = energy_balance(result)
    loss = sum(i.energy_loss for i in result.impacts)
    assert abs(sum(e["impacts"] for e in bal.values()) + loss) <= 1e-12 * pair["input"]
    assert abs(sum(e["error"] for e in bal.values()) - pair["error"]) <= 1e-12 * pair["input"]
    if name == "plastic_30deg":
        assert any(abs(e["contact_forces"]) > 1e-6 * e["input"] for e in bal.values()), "held contact did work"


def test_summary_books_each_buildings_account(tmp_path):
    """summary.json: every building's energy block has its impact work and its own balance error."""
    from pounding.io.results import write_results

    result = run(_scenes()["paper"].with_analysis(duration=3.0))
    write_results(result, tmp_path / "o")
    s = json.loads((tmp_path / "o" / "summary.json").read_text())
    for name, b in s["buildings"].items():
        e = b["energy"]
        err = e["input"] + e["contact_forces"] + e["impacts"] - e["kinetic"] - e["strain"] - e["damping"]
        assert e["error"] == pytest.approx(err, abs=1e-9 * e["input"])
        assert abs(e["relative_error"]) <= 1e-12
    assert s["energy_balance"]["energy_creating_rule"] is None


def test_the_keep_rule_is_flagged_in_summary_and_on_stderr(tmp_path):
    """after_impact = "keep" (the paper's rule) creates energy: the run warns (stderr in the CLI)
    and summary.json names the rule and the energy it created (= minus the pair's balance
    error, positive here: the paper pair gains ~1 % of its input)."""
    from pounding.io.results import write_results

    keep = _scenes()["paper"].with_analysis(duration=8.0, contact_params={"restitution": 0.5, "after_impact": "keep"})
    with pytest.warns(AnalysisWarning, match="after_impact = 'keep' creates energy"):
        result = run(keep)
    rule = energy_creating_rule(result)
    assert rule["energy_created"] == -energy_balance(result)["error"] > 0
    write_results(result, tmp_path / "o")
    flagged = json.loads((tmp_path / "o" / "summary.json").read_text())["energy_balance"]["energy_creating_rule"]
    assert flagged["rule"] == "after_impact = 'keep'" and flagged["relative"] == pytest.approx(rule["relative"])


def test_the_keep_flag_reaches_stderr_from_the_cli(tmp_path):
    """`pounding run` of the paper example with the paper's rule named (``after_impact = "keep"``; the
    default is "equilibrium" since issue 13) prints the flag on stderr."""
    import subprocess
    import sys

    text = PAPER.read_text()
    assert 'contact = "impulse"' in text
    scene = tmp_path / "keep.toml"
    scene.write_text(text.replace('contact = "impulse"', 'contact = { name = "impulse", after_impact = "keep" }'))
    proc = subprocess.run([sys.executable, "-m", "pounding", "run", str(scene), "--out", str(tmp_path / "o"), "--duration", "4", "--quiet"],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert "creates energy" in proc.stderr


def test_no_flag_without_impacts():
    """A rule that never acted creates nothing: no impacts, no flag, no warning."""
    far = load_scene(PAPER.with_name("pair_gap_0.5.toml")).with_analysis(duration=2.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error", AnalysisWarning)
        result = run(far)
    assert result.n_impacts == 0 and energy_creating_rule(result) is None
    assert np.all([e["impacts"] == 0.0 for e in building_balances(result).values()])
