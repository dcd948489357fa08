"""``pounding template``, ``pounding check`` and ``pounding reference``: writing a scene and reading it back."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from pounding.errors import InputError
from pounding.words import plural


def add_parser(sub) -> None:
    t = sub.add_parser(
        "template", help="print a commented starting scene",
        description="Print a commented starting scene (TOML) to stdout: two buildings side by side along x, 0.05 m apart, "
        "under El Centro, every key explained. Save it, edit it, then `pounding check FILE`.",
    )
    from pounding.commands.choices import elements

    t.add_argument("--element", default="frame", metavar="TYPE",
                   help=f"element type of the buildings' lateral system: {elements()}, or a plugin's type (default: frame)")
    t.set_defaults(func=cmd_template)

    c = sub.add_parser(
        "check", help="validate a scene without running it and print what was understood",
        description="Validate a scene (structure, meaning and the record) without running it, and print what was understood, "
        "with units: the ground motion, the analysis options, every building's storeys, masses, centres of mass, periods "
        "and elements, and the clear distance between facing slabs. Then the plausibility warnings (stderr). "
        "Exit code 0 if valid, 2 if not.",
    )
    c.add_argument("scene", type=Path, help="scene file (TOML)")
    add_silence(c)
    c.set_defaults(func=cmd_check)

    r = sub.add_parser(
        "reference", help="print the scene file reference (Markdown), installed plugins included",
        description="Print the scene file reference page (Markdown) generated from the schemas of the core and of every "
        "registered plugin, including those other installed packages add (docs/scene-reference.md holds the built-in ones).",
    )
    r.set_defaults(func=cmd_reference)


def add_silence(parser) -> None:
    """The --silence option of the commands that check plausibility."""
    from pounding.io.scene_schema import PLAUSIBILITY_CHECKS as NAMES  # no numpy while building the parser

    parser.add_argument("--silence", action="append", default=[], metavar="NAME",
                        help=f"do not show this plausibility warning ({', '.join(NAMES)}); repeat for more")


def silenced(args) -> tuple[str, ...]:
    """The --silence names, checked."""
    from pounding.framework.post.plausibility import NAMES
    from pounding.io.scene_structure import unknown_key_message

    for name in args.silence:
        if name not in NAMES:
            raise InputError(unknown_key_message(name, NAMES, "plausibility check"), field="--silence")
    return tuple(args.silence)


def cmd_template(args: argparse.Namespace) -> int:
    from pounding.io.scene_doc import template_text

    sys.stdout.write(template_text(args.element))
    return 0


def cmd_reference(args: argparse.Namespace) -> int:
    from pounding.io.scene_doc import reference_markdown

    sys.stdout.write(reference_markdown(installed=True))
    return 0


def cmd_check(args: argparse.Namespace) -> int:
    from pounding.framework.post import plausibility
    from pounding.io.scene import load_scene

    silence = silenced(args)
    scene = load_scene(args.scene)
    print(describe(scene, args.scene))
    found = plausibility.warn(scene, silence)
    n = len(found)
    print(f"valid scene (nothing was run); {n} plausibility warning{'' if n == 1 else 's'}" + (" on stderr" if n else ""))
    return 0


# =============================================================================
# What was understood
# =============================================================================


def describe(scene, path: Path | None = None) -> str:
    """The scene as understood, in words and tables with units."""
    import tomllib

    import numpy as np

    from pounding.contact.geometry import polygon_properties
    from pounding.framework.model.assembly import assemble

    lines = []
    title = ""
    if path is not None:
        title = tomllib.loads(Path(path).read_text()).get("title", "")
    lines.append(f"scene {path}" + (f": {title}" if title else ""))
    gm, an = scene.ground_motion, scene.analysis
    from pounding.framework.model.units import G

    gdt = f"{gm.dt:g} s" if gm.dt is not None else "non-uniform steps"
    lines.append(f"ground motion: {gm.name} ({gm.source}), {len(gm.t)} samples at {gdt}, {gm.duration:g} s, "
                 f"PGA {gm.pga / G:.4g} g = {gm.pga:.4g} m/s2, " + (
                     f"along {gm.angle:g} deg from x" if len(gm.components) == 1 else
                     f"components along {gm.angle:g} and {gm.angle + 90:g} deg from x (PGA the larger one's)"))
    from pounding.contact.rules import scene_laws
    from pounding.framework.engine.contact_step import run_dt
    from pounding.framework.engine.stacked_model import Model
    from pounding.framework.engine.integrator_choice import chosen_integrator

    integrator = chosen_integrator(scene)
    int_src = "" if an.integrator else " (chosen for the scene)"
    m = Model(scene)  # as the driver chooses (pounding.framework.engine.timestep, contact_step)
    dt, contact_time = run_dt(scene, m, *scene_laws(scene, m.pairs, m.walls), integrator)
    if an.dt:
        dt_src = ""
    elif contact_time.duration < float("inf"):
        dt_src = (f" (chosen for accuracy from the significant modes and the shortest {contact_time.law} contact, "
                  f"{contact_time.duration * 1e3:.3g} ms, in {contact_time.duration / dt:.3g} steps)")
    else:
        dt_src = " (chosen for accuracy from the significant modes)"
    duration = an.duration or gm.duration
    dur_src = "" if an.duration else " (the record's)"
    steps = int(np.ceil(duration / dt - 1e-9))
    from pounding.framework.model.registry import CONTACT_LAWS, INTEGRATORS

    def params(registry, name, given):
        """Every parameter of the plugin, the defaults it chose included."""
        from pounding.io.scene_doc import plugin_schema

        cls = registry.get(name)
        units = {k: sub.get("units", "") for k, sub in plugin_schema(cls)["properties"].items()}
        p = {k: v for k, v in cls(**given).describe().items() if k != "name"}
        text = [f"{k} = {v!r}" + (f" {units[k]}" if units.get(k) not in ("", "-", None) else "") for k, v in p.items()]
        return f" ({', '.join(text)})" if text else ""

    lines.append(f"analysis: integrator {integrator}{int_src}{params(INTEGRATORS, integrator, an.integrator_params)}, dt {dt:g} s{dt_src}, "
                 f"duration {duration:g} s{dur_src} -> {plural(steps, 'step')}; contact {an.contact}"
                 f"{params(CONTACT_LAWS, an.contact, an.contact_params)}; output every "
                 f"{'step' if an.output_every == 1 else plural(an.output_every, 'step')}; energy tolerance {100 * an.energy_tolerance:g} %"
                 + (f"; silenced: {', '.join(an.silence)}" if an.silence else ""))
    for rule in scene.contacts:  # [[contact]]: a pair of buildings with a law of its own
        lines.append(f"contact between {rule.between[0]!r} and {rule.between[1]!r}: {rule.law}{params(CONTACT_LAWS, rule.law, rule.params)}")
        if rule.bumper is not None:  # a rubber layer in the gap: its own law, then the slabs' law beyond its fraction
            b = rule.bumper
            lines.append(f"  bumper on {b.on!r} storey{'s' if len(b.storeys) > 1 else ''} {', '.join(map(str, b.storeys))}: "
                         f"{b.thickness:g} m thick, the slabs' law beyond {100 * b.compressible:g} % of it; "
                         f"layer {b.law}{params(CONTACT_LAWS, b.law, b.params)}")
    lines += [_link_line(k) for k in scene.links]  # [[link]]: a law between two slabs
    for w in scene.walls:  # [[wall]]: fixed to the ground, struck by the slabs at or below its top
        law, given = (an.contact, {**an.contact_params, **w.params}) if w.law is None else (w.law, w.params)
        face = " - ".join(f"({x:g}, {y:g})" for x, y in w.face)
        lines.append(f"wall {w.name!r}: face {face} m, top {w.top:g} m; contact {law}{params(CONTACT_LAWS, law, given)}")
    for b in scene.buildings:
        s = assemble(b)
        d = b.damping
        where = f"at periods {', '.join(f'{p:g} s' for p in d.periods)}" if d.periods else f"at mode{'s' if len(d.modes) > 1 else ''} {', '.join(map(str, d.modes))}"
        ratio = d.ratio if isinstance(d.ratio, float) else d.ratio
        damp = f"{d.kind} {100 * ratio:g} % {where}" if isinstance(ratio, float) and d.kind != "modal" else f"{d.kind} {ratio}"
        kinds: dict[str, int] = {}
        for e in b.elements:
            kinds[e.name] = kinds.get(e.name, 0) + 1
        lines.append("")
        lines.append(f"building {b.name!r}: {plural(b.n_storeys, 'storey')}, height {float(sum(b.storey_heights)):g} m, "
                     f"{plural(len(b.elements), 'element')} ({', '.join(f'{k} x{n}' for k, n in kinds.items())}), damping {damp}")
        lines.append(f"  {'storey':>6} {'h [m]':>6} {'z [m]':>6} {'area [m2]':>10} {'mass [t]':>9} {'[kg/m2]':>8} {'CM x, y [m]':>16} {'J [t m2]':>10}")
        for f, slab in enumerate(b.slabs):
            area = polygon_properties(slab.vertices)[0]
            lines.append(f"  {f + 1:>6} {b.storey_heights[f]:>6.3g} {slab.elevation:>6.4g} {area:>10.4g} {slab.mass / 1e3:>9.4g} "
                         f"{slab.mass / area:>8.4g} {slab.centre[0]:>7.3f},{slab.centre[1]:>8.3f} {slab.polar_inertia / 1e3:>10.4g}")
        T = s.periods
        lines.append("  periods [s]: " + ", ".join(f"T{i + 1} = {t:.4g}" for i, t in enumerate(T[: min(6, len(T))])) + (" ..." if len(T) > 6 else ""))
        for k, e in enumerate(b.elements):
            a, c = (np.round(p, 9) + 0.0 for p in e.plan_segment())
            angle = float(np.degrees(np.arctan2(e.direction[1], e.direction[0])))
            fl = e.building_floors
            span = f"floor {fl[0]}" if len(fl) == 1 else f"floors {fl[0]}-{fl[-1]}"
            span += f", standing on floor {e.base_floor}" if e.base_floor else ""
            lines.append(f"  element[{k}] {e.name}: ({a[0]:g}, {a[1]:g}) to ({c[0]:g}, {c[1]:g}) m, at {angle:g} deg, {span}")
    pairs = _facing(scene)
    if pairs:
        lines.append("")
        for text in pairs:
            lines.append(text)
    return "\n".join(lines)


def _link_line(link) -> str:
    """One line of `pounding check` for a link: where its ends are and its law with its parameters."""
    (pa, pb), (a, b) = link.points, link.between
    law = ", ".join(f"{key} = {v:g}" if isinstance(v, float) else f"{key} = {v}" for key, v in link.law.describe().items())
    return (f"link {link.name!r}: {a!r} storey {link.storeys[0]} at ({pa[0]:g}, {pa[1]:g}) m to {b!r} storey "
            f"{link.storeys[1]} at ({pb[0]:g}, {pb[1]:g}) m; {law}")


def _facing(scene) -> list[str]:
    """The clear distance at rest between the slabs of every two buildings at a common level."""
    from pounding.contact.geometry import signed_gap
    from pounding.framework.model.placement import adjacent_pairs
    from pounding.framework.model.levels import common_levels

    out = []
    bs = scene.buildings
    screened = set(adjacent_pairs(scene)[1]) if len(bs) > 2 else set()
    for i in range(len(bs)):
        for j in range(i + 1, len(bs)):
            gaps = [(fa + 1, signed_gap(bs[i].slabs[fa].vertices, bs[j].slabs[fb].vertices)) for fa, fb in common_levels(bs[i], bs[j])]
            if gaps:
                g = min(g for _, g in gaps)
                levels = f"storey {gaps[0][0]}" if len(gaps) == 1 else f"storeys {gaps[0][0]}-{gaps[-1][0]}"
                out.append(f"{bs[i].name!r} and {bs[j].name!r}: slabs at a common level at {levels}; smallest clear distance at rest {g:.4g} m"
                           + ("; not adjacent (a building stands between them at every common level)" if (i, j) in screened else ""))
            else:
                out.append(f"{bs[i].name!r} and {bs[j].name!r}: no slabs at a common level (they cannot pound slab to slab)")
    return out
