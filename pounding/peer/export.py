"""``pounding export opensees``: an OpenSeesPy script of a scene's model, to check a result in OpenSees.

The script is what the peer builders of :mod:`pounding.peer.opensees` do in memory for the
cross-check tests, written down: they are driven with a :class:`~pounding.peer.script.ScriptOps`
instead of ``openseespy.opensees``, so the exported model and the tested one are the same
commands. It holds

* every building as :func:`pounding.peer.opensees.build_building` models it: rigid diaphragms
  (a master node at each slab's centre of mass with its mass and polar inertia), frames as
  planar frames of ``elasticBeamColumn`` members, walls as ``ElasticTimoshenkoBeam`` chains,
  storey springs as ``twoNodeLink`` elements with ``Elastic``, ``Steel01`` or ``BoucWen``;
* each building's Rayleigh damping C = a0 M + a1 K_initial
  (:func:`~pounding.peer.opensees.rayleigh_damping`);
* the ground motion as ``UniformExcitation`` (:func:`~pounding.peer.opensees.uniform_excitation`);
* walls fixed to the ground as :func:`pounding.peer.opensees_walls.scene_walls` builds them: a fixed
  node and a ``zeroLength`` element with the wall's contact material at each end of every slab edge
  facing a straight face along y (a wall the peer cannot model is left out and the script says why);
* links between slabs (``[[link]]``) as :func:`pounding.peer.opensees_links.scene_links` builds them:
  a ``zeroLength`` element along the link's line with its law's material (``Elastic``, ``Viscous``,
  ``ViscousDamper``, ``Parallel``, ``Steel01``, ``BoucWen``) between a node on each slab's diaphragm;
* contact as ``zeroLength`` elements between two buildings with collinear facing facades along x
  (:func:`~pounding.peer.opensees.face_springs`), with the OpenSees material of the pair's force
  law (:mod:`pounding.peer.opensees_contact`: ``ViscoelasticGap`` for kelvin, ``Hertzdamp`` for
  hertz and hertzdamp, ``JankowskiImpact`` for jankowski, ``ElasticPPGap`` for penalty's springs
  and for material with an elastic or bilinear link law); the rigid impulse law, and material with
  any other link law, have no OpenSees material and are left out, and where a material differs
  from the law (penalty's dashpot, kelvin without tension, Hertzdamp's impact velocity, a
  bilinear material's lower bound) the script says so;
* a Newton transient analysis with the scene's integrator where OpenSees has it (``newmark``
  as ``Newmark``; ``hht`` as ``HHT_TP`` with alpha 1 + Hilber's alpha), else Newmark average
  acceleration, at the time step and for the number of steps the tool would use.

Run it with ``python model.py``: it prints the first periods and writes the master nodes'
displacement histories to a CSV file (``--help`` for options).
"""

from __future__ import annotations

import inspect
from pathlib import Path

import numpy as np

from pounding.peer.script import ScriptOps

#: Out-of-plane bending inertia and torsional constant of every member, as a fraction of its
#: in-plane one: OpenSees needs some to keep planar frames stable; periods move by about this
#: relative amount (tests/test_opensees_transient.py measures the deviation it causes)
OUT_OF_PLANE = 1e-9
#: Newton's NormDispIncr tolerance [m] of the exported analysis, and its iteration limit
TOLERANCE = 1e-12
MAX_ITERATIONS = 50
#: Number of periods the script prints by default (its eigen solution is dense: see the docs)
MODES = 6


def opensees_script(scene, *, out_of_plane: float = OUT_OF_PLANE) -> tuple[str, list[str]]:
    """The OpenSeesPy script of ``scene`` (module docstring) and the notes on what it leaves out.

    Parameters
    ----------
    scene : Scene
    out_of_plane : float
        See :func:`pounding.peer.opensees.build_building` [-], > 0.

    Returns
    -------
    (script, notes) : str, list of str
        The Python source, and one sentence per part of the model OpenSees does not get
        (also written as comments at the top of the script).

    Raises
    ------
    InputError
        For an element type, damping kind or link law the peer model does not have.
    """
    from pounding.errors import InputError

    ops = ScriptOps()
    try:
        masters, notes = _model(ops, scene, out_of_plane)
    except (NotImplementedError, ValueError) as exc:
        raise InputError(f"cannot export to OpenSees: {exc}") from None
    integrator, note = _integrator(scene)
    notes += [note] if note else []
    analysis = ScriptOps()
    from pounding.peer.opensees import transient_analysis

    transient_analysis(analysis, integrator, TOLERANCE, MAX_ITERATIONS)
    dt, steps, note = _time_grid(scene)
    notes += [note] if note else []
    return _render(scene, ops, analysis, masters, dt, steps, notes, integrator), notes


# --------------------------------------------------------------------------- the model
def _model(ops: ScriptOps, scene, out_of_plane: float) -> tuple[dict[str, list[int]], list[str]]:
    """Record the buildings, their damping, the ground motion and the contact springs; returns
    (master tags per building, notes)."""
    from pounding.peer.opensees import _build, _Tags, building_rayleigh, rayleigh_damping, uniform_excitation

    ops.wipe()
    tags = _Tags(0)
    built = {}
    for b in scene.buildings:
        ops.comment(f"building {b.name!r}: {b.n_storeys} storeys")
        built[b.name] = _build(ops, b, out_of_plane, tags)
    ops.comment("each building's Rayleigh damping C = a0 M + a1 K_initial")
    rayleigh_damping(ops, [built[b.name][1:3] for b in scene.buildings], building_rayleigh(scene.buildings))
    masters = {name: parts[0] for name, parts in built.items()}
    ops.comment("contact")
    notes = _contact(ops, scene, masters, tags)
    notes += _walls(ops, scene, masters, tags)
    _links(ops, scene, masters, tags)
    ops.comment("the ground motion (accelerations [m/s2])")
    uniform_excitation(ops, scene.ground_motion)
    return masters, notes


def _contact(ops: ScriptOps, scene, masters: dict, tags) -> list[str]:
    """Contact elements where OpenSees has the pair's contact law (:mod:`pounding.peer.opensees_contact`);
    notes on what is left out or differs."""
    from pounding.contact.rules import law_name
    from pounding.framework.model.registry import watches_contact
    from pounding.peer.opensees import face_springs
    from pounding.peer.opensees_contact import WITH_MATERIAL, has_material, law_material, pair_law

    if not watches_contact(scene.analysis):  # as in a run: no pair is watched, whatever its [[contact]] rule
        ops.comment(f"none: the scene's contact law {scene.analysis.contact!r} switches contact off")
        return []
    if len(scene.buildings) == 1:
        ops.comment("one building: no pair of buildings to pound")
        return []
    if len(scene.buildings) != 2:
        note = "contact elements are written for a pair of buildings only: the script has no contact"
        ops.comment(note)
        return [note]
    pair = sorted(scene.buildings, key=lambda b: float(np.mean(b.slabs[0].vertices[:, 0])))
    try:
        law = pair_law(scene, *pair)
    except ValueError as exc:
        note = f"no contact elements ({exc}): the script has no contact"
        ops.comment(note)
        return [note]
    if not has_material(law):
        why = " (OpenSees has no rigid impulse at events)" if law.at_events else ""
        note = (f"contact law {law_name(law)!r} has no OpenSees material{why}: "
                "the script has no contact; compare contact-free histories, or export a scene with a force law "
                f"that has one ({WITH_MATERIAL})")
        ops.comment(note)
        return [note]
    try:
        face_springs(ops, pair, masters, law_material(law), tags)
    except ValueError as exc:
        note = f"no contact elements ({exc}; they are written for facades facing each other along x): the script has no contact"
        ops.comment(note)
        return [note]
    notes = law.opensees_notes()
    for note in notes:
        ops.comment(note)
    return notes


def _walls(ops: ScriptOps, scene, masters: dict, tags) -> list[str]:
    """The walls as the tests' peer model builds them (:func:`pounding.peer.opensees_walls.scene_walls`: a
    fixed node and a zeroLength element with the wall's law's material at each end of every slab edge
    facing it); notes on the walls left out and on materials that differ from their law."""
    from pounding.peer.opensees_walls import scene_walls

    if not scene.walls:
        return []
    ops.comment("walls fixed to the ground: a fixed node and a zero-length gap element at each end of every slab edge facing one")
    _, left_out, differs = scene_walls(ops, scene, masters, tags)
    for note in left_out + differs:
        ops.comment(note)
    return left_out + differs


def _links(ops: ScriptOps, scene, masters: dict, tags) -> None:
    """The ``[[link]]`` tables as the tests' peer model builds them (:func:`pounding.peer.opensees_links.scene_links`:
    a zeroLength element with the law's material between a node on each slab, slaves of their diaphragms).
    A law with no OpenSees material raises NotImplementedError (the export's one message)."""
    from pounding.peer.opensees_links import scene_links

    if not scene.links:
        return
    ops.comment("links between slabs: zero-length elements along each link's line, with its law's material")
    scene_links(ops, scene, masters, tags)


def _integrator(scene) -> tuple[tuple, str | None]:
    """The ``ops.integrator`` arguments for the scene's integrator, and a note when it has none in OpenSees."""
    from pounding.framework.engine.integrator_choice import chosen_integrator
    from pounding.framework.model.registry import INTEGRATORS

    name = chosen_integrator(scene)
    params = INTEGRATORS.get(name)(**scene.analysis.integrator_params).describe() if scene.analysis.integrator == name else {}
    if name == "newmark":
        return ("Newmark", float(params.get("gamma", 0.5)), float(params.get("beta", 0.25))), None
    if name == "hht":
        # OpenSees' alpha is 1 + Hilber's; HHT_TP weights the (yielding) forces as pounding blends them
        return ("HHT_TP", 1.0 + float(params.get("alpha", -0.05))), None
    return ("Newmark", 0.5, 0.25), (f"integrator {name!r} has no OpenSees counterpart: the script uses Newmark average "
                                    "acceleration (run pounding with integrator = 'newmark' to compare like with like)")


def _time_grid(scene) -> tuple[float, int, str | None]:
    """(dt [s], steps, note) the tool would use: the scene's step, or its default step
    (pounding.framework.engine.timestep), and a note when the scene's own step spans a force law's
    shortest contact in fewer steps than the default takes (the tool's run warns of it too; OpenSees'
    Newton may then fail inside the contact), else None."""
    from pounding.contact.rules import scene_laws
    from pounding.framework.engine.contact_step import run_dt
    from pounding.framework.engine.stacked_model import Model
    from pounding.framework.engine.integrator_choice import chosen_integrator
    from pounding.framework.engine.timestep import STEPS_PER_CONTACT

    an, gm = scene.analysis, scene.ground_motion
    m = Model(scene)  # as the driver chooses: the modes and the shortest contact (pounding.framework.engine.contact_step)
    dt, contact = run_dt(scene, m, *scene_laws(scene, m.pairs, m.walls),
                         chosen_integrator(scene))
    note = None
    per = contact.duration / dt
    if per < STEPS_PER_CONTACT * (1.0 - 1e-9):
        note = (f"dt = {dt:g} s spans the shortest {contact.law} contact ({contact.duration * 1e3:.3g} ms) in {per:.3g} steps "
                f"(the default step takes {STEPS_PER_CONTACT}): OpenSees' Newton may fail inside such a contact; "
                f"dt <= {contact.duration / STEPS_PER_CONTACT:.3g} s resolves it (leave [analysis] dt out for the default)")
    duration = float(an.duration or gm.duration)
    return dt, max(1, int(np.ceil(duration / dt - 1e-9))), note


# --------------------------------------------------------------------------- the script
_MAIN = '''

def periods(n):
    """The first n natural periods of the model [s], longest first."""
    return eigen_periods(ops, n)


def run(history, steps=STEPS):
    """Integrate `steps` steps of DT and write every master node's ux [m], uy [m], rz [rad] to `history` (CSV)."""
    analysis()
    columns = ["time [s]"] + [f"{name}.{floor + 1}.{dof}" for name, tags in MASTERS.items()
                              for floor in range(len(tags)) for dof in ("u [m]", "v [m]", "phi [rad]")]
    with open(history, "w", newline="") as fh:
        out = csv.writer(fh)
        out.writerow(columns)
        out.writerow([0.0] * len(columns))
        for k in range(1, steps + 1):
            if ops.analyze(1, DT) != 0:
                sys.exit(f"OpenSees analysis failed at step {k} (t = {k * DT:g} s)")
            out.writerow([k * DT] + [ops.nodeDisp(tag, dof) for tags in MASTERS.values() for tag in tags for dof in (1, 2, 6)])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--history", default=str(Path(__file__).with_name(Path(__file__).stem + "_history.csv")),
                        help="CSV file of the master nodes' displacement histories (default: beside this script)")
    parser.add_argument("--modes", type=int, default=MODES, help="number of periods to print (0: none)")
    parser.add_argument("--steps", type=int, default=STEPS, help="number of time steps of DT (default: the scene's duration)")
    args = parser.parse_args(argv)
    build()
    if args.modes > 0:
        print(json.dumps({"periods [s]": [float(t) for t in periods(args.modes)]}))
    run(args.history, args.steps)
    print(f"histories written to {args.history}")


if __name__ == "__main__":
    main()
'''


def _render(scene, ops: ScriptOps, analysis: ScriptOps, masters: dict, dt: float, steps: int, notes: list[str],
            integrator: tuple) -> str:
    from pounding.peer.opensees import eigen_periods, load_opensees

    from importlib.metadata import version

    import textwrap

    title = f"{scene.source.name}" if scene.source is not None else "a scene built in Python"
    left_out = "".join("\n" + textwrap.fill(f"Left out: {n}", 100) for n in notes)
    head = f'''"""OpenSeesPy model of {title}, written by pounding {version("pounding")} (`pounding export opensees`).

Units: m, N, kg, s. Every floor is a rigid diaphragm (a master node at the slab's centre of mass
carrying its mass and polar inertia; ux, uy, rz free); frames are planar frames of elastic
beam-columns, walls Timoshenko beams, storey springs twoNodeLink elements; retaining walls are
fixed nodes with zero-length gap elements to the slabs' edges, links between slabs zero-length
elements along their lines; each building has its own Rayleigh damping; the ground motion is a
UniformExcitation; the analysis is
integrator{integrator!r}, dt = {dt!r} s, {steps} steps.
{left_out}
Run: python {{this file}} [--history FILE] [--modes N] [--steps N]
"""
'''
    loader = inspect.getsource(load_opensees)
    eigen = inspect.getsource(eigen_periods)
    parts = [
        head,
        "import argparse\nimport csv\nimport ctypes\nimport importlib.util\nimport json\nimport sys\nfrom pathlib import Path\n\nimport numpy as np\n\n",
        "\n", loader, "\n\nops = load_opensees()\n\n",
        f"DT = {dt!r}  # [s]\nSTEPS = {steps}\nMODES = {MODES}\n",
        "#: building name -> master node tag of every floor, bottom first\n",
        f"MASTERS = {{{', '.join(f'{k!r}: {v!r}' for k, v in masters.items())}}}\n\n",
        ops.data_source(), "\n\n\n",
        'def build():\n    """Wipe the domain and build the model: buildings, damping, contact, ground motion."""\n',
        ops.source("    "), "\n\n\n",
        'def analysis():\n    """The transient analysis (Newton; rigid diaphragms need the Transformation handler)."""\n',
        analysis.source("    "), "\n\n\n",
        eigen, _MAIN,
    ]
    return "".join(parts)


def write_script(scene, out: str | Path, *, out_of_plane: float = OUT_OF_PLANE) -> list[str]:
    """Write :func:`opensees_script` to ``out`` (through a temporary file renamed into place:
    no partial file on failure); returns the notes."""
    import os
    import tempfile

    text, notes = opensees_script(scene, out_of_plane=out_of_plane)
    out = Path(out)
    fd, tmp = tempfile.mkstemp(prefix=f".{out.name}.", dir=out.parent)
    try:
        with os.fdopen(fd, "w") as fh:
            fh.write(text)
        os.replace(tmp, out)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return notes
