"""Read a scene file (TOML) into a validated, immutable :class:`~pounding.framework.model.scene.Scene`.

Checks run in three layers, each stopping at the first problem with one
message naming the file, the key path (``building[0].element[2].columns``)
and what was expected:

1. TOML syntax (``tomllib``);
2. structure (:mod:`pounding.io.scene_structure`): non-finite numbers (TOML
   allows nan/inf), keys, types and ranges against the JSON schemas
   (``jsonschema``) of the core and of each element plugin, plugin names and
   parameters; unknown keys first, with the closest known one;
3. meaning: polygon validity, one value per storey, mass and inertia, elements
   standing on their slabs, slabs overlapping at rest, plugin names and
   parameters, the ground-motion record.
"""

from __future__ import annotations

import inspect
import tomllib
from dataclasses import replace
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from pounding.errors import InputError
from pounding.framework.model.levels import LEVEL_TOL, distance_to_polygon, same_level
from pounding.framework.model.scene import Analysis, Building, Bumper, ContactRule, Damping, Scene, Slab, Wall
from pounding.framework.model.walls import check_wall
from pounding.io.scene_structure import _path, framework_element_keys, scene_problems



# --------------------------------------------------------------------------- buildings
def _per_storey(table: Mapping, key: str, n: int, where: list) -> list:
    value = table[key]
    if isinstance(value, list):
        if len(value) != n:
            raise InputError(f"expected one value or a list of {n} (one per storey), got {len(value)}", field=_path(where + [key]))
        return list(value)
    return [value] * n


def _slab_polygons(table: Mapping, n: int, where: list) -> list[np.ndarray]:
    from pounding.contact.geometry import ccw, is_simple

    if ("slab" in table) == ("slabs" in table):
        raise InputError("give exactly one of slab (one polygon for every storey) or slabs (one per storey)", field=_path(where + ["slab"]))
    if "slab" in table:
        polys, keys = [table["slab"]] * n, [["slab"]] * n
    else:
        if len(table["slabs"]) != n:
            raise InputError(f"expected {n} polygons (one per storey), got {len(table['slabs'])}", field=_path(where + ["slabs"]))
        polys, keys = table["slabs"], [["slabs", i] for i in range(n)]
    out = []
    for poly, key in zip(polys, keys):
        v = np.asarray(poly, dtype=float)
        ok, reason = is_simple(v)
        if not ok:
            raise InputError(f"the slab polygon is not a simple polygon: {reason}", field=_path(where + key))
        out.append(ccw(v))
    return out


def _damping(table: Mapping | None, where: list) -> Damping:
    if table is None:
        return Damping()
    kind = table.get("type", "rayleigh")
    ratio = table.get("ratio", 0.05)
    field = _path(where + ["damping"])
    if kind == "rayleigh":
        if isinstance(ratio, list):
            raise InputError("Rayleigh damping takes one ratio", field=field + ".ratio")
        if "periods" in table and "modes" in table:
            raise InputError("give modes or periods, not both", field=field)
        modes = tuple(table.get("modes", (1, 3)))
        if "periods" not in table and (len(modes) != 2 or modes[0] == modes[1]):
            raise InputError("Rayleigh damping needs two different modes, e.g. [1, 3]", field=field + ".modes")
        periods = tuple(float(p) for p in table["periods"]) if "periods" in table else None
        if periods is not None and periods[0] == periods[1]:
            raise InputError("Rayleigh damping needs two different periods", field=field + ".periods")
        return Damping("rayleigh", float(ratio), modes, periods)
    if kind == "modal":
        return Damping("modal", tuple(float(r) for r in ratio) if isinstance(ratio, list) else float(ratio), ())
    if isinstance(ratio, list):
        raise InputError("stiffness-proportional damping takes one ratio", field=field + ".ratio")
    modes = tuple(table.get("modes", (1,)))
    if len(modes) != 1:
        raise InputError("stiffness-proportional damping takes one mode, e.g. [1]", field=field + ".modes")
    return Damping("stiffness", float(ratio), modes)


def _building(table: Mapping, index: int) -> Building:
    from pounding.contact.geometry import polygon_properties
    from pounding.framework.model.registry import ELEMENTS

    where = ["building", index]
    heights = tuple(float(h) for h in table["storey_heights"])
    n = len(heights)
    polys = _slab_polygons(table, n, where)
    props = [polygon_properties(p) for p in polys]  # (area, centroid, polar moment about centroid)

    if ("mass" in table) == ("mass_per_area" in table):
        raise InputError("give exactly one of mass [kg] or mass_per_area [kg/m2]", field=_path(where + ["mass"]))
    if "mass" in table:
        masses = [float(m) for m in _per_storey(table, "mass", n, where)]
    else:
        masses = [float(m) * a for m, (a, _, _) in zip(_per_storey(table, "mass_per_area", n, where), props)]

    centres = [c for _, c, _ in props]
    if "centre_of_mass" in table:
        cm = table["centre_of_mass"]
        if len(cm) != n:
            raise InputError(f"expected {n} points (one per storey), got {len(cm)}", field=_path(where + ["centre_of_mass"]))
        centres = [np.asarray(c, dtype=float) for c in cm]
    if "polar_inertia" in table:
        J = table["polar_inertia"]
        if len(J) != n:
            raise InputError(f"expected {n} values (one per storey), got {len(J)}", field=_path(where + ["polar_inertia"]))
        inertia = [float(j) for j in J]
    else:
        # uniform lamina: m * Ip / A about the centroid, moved to the centre of mass by parallel axes
        inertia = [m * (ip / a + float(np.sum((c - c0) ** 2))) for m, (a, c0, ip), c in zip(masses, props, centres)]

    elevations = np.cumsum(heights)
    slabs = tuple(
        Slab(vertices=p, mass=m, centre=np.asarray(c, dtype=float), polar_inertia=j, elevation=float(z))
        for p, m, c, j, z in zip(polys, masses, centres, inertia, elevations)
    )

    elements, modifiers = [], []
    for k, etable in enumerate(table.get("element", [])):
        ewhere = where + ["element", k]
        cls = ELEMENTS.get(etable["type"], field=_path(ewhere + ["type"]))
        # keys of every element type (scene_schema.BUILDING) are the framework's, not the plugin's
        modifiers.append(float(etable.get("stiffness_modifier", 1.0)))
        body = {key: val for key, val in etable.items() if key not in framework_element_keys()}  # checked by scene_problems
        try:
            element = cls.build(body, storey_heights=heights, first_storey=etable.get("first_storey", 1))
        except InputError as exc:
            raise exc.located(field_prefix=_path(ewhere)) from None
        _check_on_slabs(element, slabs, ewhere)
        if element.yields and modifiers[-1] != 1.0:
            # the modifier scales the modal stiffness, not the law's parameters: the two would disagree
            raise InputError("a yielding element takes no stiffness_modifier: scale its law's stiffness and yield force instead",
                             field=_path(ewhere + ["stiffness_modifier"]))
        elements.append(element)
    if not elements:
        raise InputError(f"building {table['name']!r} has no elements: add frames or walls", field=_path(where + ["element"]))
    return Building(
        table["name"], heights, slabs, tuple(elements), _damping(table.get("damping"), where),
        modifiers=tuple(modifiers) if any(m != 1.0 for m in modifiers) else None,
        p_delta=_p_delta(table.get("p_delta"), n, where),
    )


def _p_delta(table: Mapping | None, n: int, where: list):
    from pounding.framework.model.scene import PDelta

    if table is None:
        return None
    if "loads" in table and "load_factor" in table:
        raise InputError("give loads [N] or load_factor, not both", field=_path(where + ["p_delta"]))
    if "loads" in table:
        if len(table["loads"]) != n:
            raise InputError(f"expected {n} loads [N] (one per floor), got {len(table['loads'])}", field=_path(where + ["p_delta", "loads"]))
        return PDelta(loads=tuple(float(w) for w in table["loads"]))
    return PDelta(load_factor=float(table.get("load_factor", 1.0)))


def interior_point(vertices: np.ndarray) -> np.ndarray:
    """A point strictly inside a simple polygon (its centroid, unless that falls outside, as in
    an L's notch: then the centroid of an ear triangle that contains no other vertex)."""
    from pounding.contact.geometry import polygon_properties

    c = polygon_properties(vertices)[1]
    if _strictly_inside(vertices, c):
        return c
    k = len(vertices)
    for i in range(k):
        tri = vertices[[(i - 1) % k, i, (i + 1) % k]]
        p = tri.mean(axis=0)
        if _strictly_inside(vertices, p):
            return p
    return c


def _strictly_inside(vertices: np.ndarray, p: np.ndarray) -> bool:
    a, b = vertices, np.roll(vertices, -1, axis=0)
    ab, ap = b - a, p - a
    t = np.clip(np.einsum("ij,ij->i", ap, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    on_boundary = np.min(np.hypot(*(ap - t[:, None] * ab).T)) <= LEVEL_TOL
    return not on_boundary and distance_to_polygon(vertices, p) == 0.0


def _check_on_slabs(element, slabs, where: list) -> None:
    a, b = element.plan_segment()
    base = (element.base_floor,) if element.base_floor > 0 else ()  # the slab it stands on carries it too
    for f in base + element.building_floors:
        slab = slabs[f - 1]
        for name, p in (("start", a), ("end", b)):
            if distance_to_polygon(slab.vertices, p) > LEVEL_TOL:
                raise InputError(
                    f"the element's {name} point ({p[0]:g}, {p[1]:g}) lies outside the slab of storey {f}",
                    field=_path(where),
                )


def _check_apart_at_rest(buildings: list[Building]) -> None:
    """Refuse two buildings that occupy the same space at rest.

    Storey k of a building is the prism of its slab k between the floor below
    (elevation z_{k-1}, the ground for k = 1) and its own level z_k: its columns
    and walls stand there. Two storeys whose height ranges share more than
    LEVEL_TOL and whose plans overlap (or lie one inside the other) are one
    space claimed twice, whether or not their slabs are at a common level.
    """
    from pounding.contact.geometry import rest_gap as signed_gap  # interpreted: compiles nothing

    boxes = [[(s.vertices.min(axis=0), s.vertices.max(axis=0)) for s in b.slabs] for b in buildings]
    for i, a in enumerate(buildings):
        for j in range(i + 1, len(buildings)):
            b = buildings[j]
            for fa, sa in enumerate(a.slabs):
                za = (a.slabs[fa - 1].elevation if fa else 0.0, sa.elevation)
                for fb, sb in enumerate(b.slabs):
                    zb = (b.slabs[fb - 1].elevation if fb else 0.0, sb.elevation)
                    if min(za[1], zb[1]) - max(za[0], zb[0]) <= LEVEL_TOL:
                        continue  # the storeys share no height
                    (lo_a, hi_a), (lo_b, hi_b) = boxes[i][fa], boxes[j][fb]
                    if np.any(lo_a > hi_b + LEVEL_TOL) or np.any(lo_b > hi_a + LEVEL_TOL):
                        continue  # plan boxes apart: so are the polygons
                    g = signed_gap(sa.vertices, sb.vertices)
                    # a slab lying over another (even coincident) has its centroid inside the other
                    nested = distance_to_polygon(sb.vertices, interior_point(sa.vertices)) == 0.0 or distance_to_polygon(sa.vertices, interior_point(sb.vertices)) == 0.0
                    if not (g < -LEVEL_TOL or (nested and g >= -LEVEL_TOL)):
                        continue
                    if same_level(sa.elevation, sb.elevation):
                        where = f"the slabs of {a.name!r} and {b.name!r} at storey {fa + 1}"
                    else:
                        where = (f"storey {fa + 1} of {a.name!r} ({za[0]:g}-{za[1]:g} m) and storey {fb + 1} of {b.name!r} "
                                 f"({zb[0]:g}-{zb[1]:g} m), at different levels but sharing heights,")
                    how = f"overlap by {-g:.4g} m at rest" if g < -LEVEL_TOL else "lie on top of each other at rest"
                    raise InputError(f"{where} {how}", field=_path(["building", j, "slab"]))


# --------------------------------------------------------------------------- analysis
def _plugin(value: Any, registry, field: str, search: tuple = ()) -> tuple[str, dict]:
    """(name, parameters) of a plugin given as a name or ``module:Class`` (``search``: folders to find
    the module in), or a table ``{ name = ..., parameter = ... }``; the class is looked up and its
    parameters checked here."""
    if isinstance(value, str):
        name, params = value, {}
    else:
        params = dict(value)
        name = params.pop("name")
        field = f"{field}.name"
    cls = registry.get(name, field=field, search=search)
    _check_params(cls, params, field.removesuffix(".name"))
    return name, params


def _check_params(cls, params: dict, field: str) -> None:
    try:
        cls(**params)
    except TypeError:
        sig = inspect.signature(cls.__init__)
        accepted = [p for p in sig.parameters if p != "self" and sig.parameters[p].kind is inspect.Parameter.KEYWORD_ONLY]
        bad = [k for k in params if k not in accepted]
        raise InputError(
            f"unknown parameter(s) {', '.join(bad) or '?'} for {cls.name!r}; accepted: {', '.join(accepted) or 'none'}", field=field
        ) from None
    except InputError as exc:
        raise exc.located(field_prefix=field) from None


def _analysis(table: Mapping, search: tuple = ()) -> Analysis:
    from pounding.framework.model.registry import CONTACT_LAWS, INTEGRATORS

    integrator, iparams = (None, {}) if "integrator" not in table else _plugin(table["integrator"], INTEGRATORS, "analysis.integrator", search)
    contact, cparams = _plugin(table.get("contact", "impulse"), CONTACT_LAWS, "analysis.contact", search)
    if "restitution" in table:
        cparams.setdefault("restitution", float(table["restitution"]))
        _check_params(CONTACT_LAWS.get(contact, search=search), cparams, "analysis.restitution")
    force = dict(table.get("impact_force", {}))
    model = force.get("model", "hertz")
    for key, owner in (("stiffness", "hertz"), ("duration", "duration")):
        if key in force and model != owner:
            raise InputError(f"{key} applies to model = {owner!r}, not {model!r}", field=f"analysis.impact_force.{key}")
    return Analysis(
        integrator=integrator,
        integrator_params=iparams,
        dt=table.get("dt"),
        duration=table.get("duration"),
        contact=contact,
        contact_params=cparams,
        output_every=int(table.get("output_every", 1)),
        energy_tolerance=float(table.get("energy_tolerance", 0.02)),
        impact_force=dict(table.get("impact_force", {})),
        silence=tuple(table.get("silence", ())),
    )


def _contact_rules(tables: list, buildings: list[Building], analysis: Analysis, search: tuple) -> tuple[ContactRule, ...]:
    """The ``[[contact]]`` tables: the law of the slab pairs between two named buildings, and their bumpers."""
    from pounding.framework.model.registry import CONTACT_LAWS

    names = [b.name for b in buildings]
    default = CONTACT_LAWS.get(analysis.contact, search=search)
    out, seen = [], {}
    for i, table in enumerate(tables):
        where = f"contact[{i}]"
        between = list(table["between"])
        for j, nm in enumerate(between):
            if nm not in names:
                raise InputError(f"no building is named {nm!r}; the buildings: {', '.join(map(repr, names))}",
                                 field=f"{where}.between[{j}]")
        if between[0] == between[1]:
            raise InputError(f"expected two different buildings, got {between[0]!r} twice", field=f"{where}.between")
        key = frozenset(between)
        if key in seen:
            raise InputError(f"the pair {between[0]!r} - {between[1]!r} already has its law in contact[{seen[key]}]",
                             field=f"{where}.between")
        seen[key] = i
        if "law" not in table and "bumper" not in table:
            raise InputError("expected a law, a bumper or both", field=where)
        if "law" in table:
            law, params = _own_law(table["law"], analysis, f"{where}.law", search)
            if law is None:  # [analysis] contact's, with parameters of its own
                law, params = analysis.contact, {**analysis.contact_params, **params}
            # the rule the run applies (contact.rules.pair_laws): a force law, or [analysis] contact's impulse law
            # with at most a restitution of its own
            problem = CONTACT_LAWS.get(law, search=search)(**params).own_law_problem(default(**analysis.contact_params))
            if problem is not None:
                raise InputError(problem, field=f"{where}.law")
        else:  # the slabs' law under a bumper: [analysis] contact's
            law, params = analysis.contact, dict(analysis.contact_params)
        rule = ContactRule((between[0], between[1]), law, params)
        if "bumper" in table:
            rule = replace(rule, bumper=_bumper(table["bumper"], rule, buildings, default, analysis, search, f"{where}.bumper"))
        out.append(rule)
    return tuple(out)


def _own_law(value, analysis: Analysis, field: str, search: tuple) -> tuple[str | None, dict]:
    """(name, parameters) of the law a ``[[contact]]`` table or a ``[[wall]]`` gives its pairs: a name,
    ``module:Class`` or a table with a name (:func:`_plugin`); or a table without one, ``[analysis]
    contact``'s law with parameters of its own (a restitution): (None, those parameters), checked
    over ``[analysis] contact``'s."""
    from pounding.framework.model.registry import CONTACT_LAWS

    if isinstance(value, str) or "name" in value:
        return _plugin(value, CONTACT_LAWS, field, search)
    params = dict(value)
    _check_params(CONTACT_LAWS.get(analysis.contact, search=search), {**analysis.contact_params, **params}, field)
    return None, params


def _mixing_problem(analysis: Analysis, search: tuple) -> str | None:
    """Why ``[analysis] contact`` cannot take force laws on some pairs beside it, or None
    (:meth:`~pounding.contact.base.ContactLaw.mixing_problem`)."""
    from pounding.framework.model.registry import CONTACT_LAWS

    return CONTACT_LAWS.get(analysis.contact, search=search)(**analysis.contact_params).mixing_problem()


def _bumper(table: Mapping, rule: ContactRule, buildings: list[Building], default: type, analysis: Analysis, search: tuple,
            where: str) -> Bumper:
    """A ``[[contact]]`` table's ``bumper`` (:mod:`pounding.framework.model.bumpers`), checked: its
    building, storeys, thickness and fraction, and that the layer's and the slabs' laws act by forces."""
    from pounding.contact.geometry import rest_gap
    from pounding.framework.model.bumpers import check_bumper
    from pounding.framework.model.registry import CONTACT_LAWS

    if not CONTACT_LAWS.get(rule.law, search=search).with_step:
        raise InputError(f"a bumper needs a force law for the slabs it stands between, and {rule.law!r} acts by impulses: give "
                         "this [[contact]] a force law (law = \"kelvin\", \"hertzdamp\", \"penalty\"...) or [analysis] contact one",
                         field=where)
    problem = _mixing_problem(analysis, search) if default.at_events else None
    if problem is not None:
        raise InputError(problem, field=where)
    law, params = _plugin(table["law"], CONTACT_LAWS, f"{where}.law", search)
    if not CONTACT_LAWS.get(law, search=search).with_step:
        raise InputError(f"a bumper needs a force law (a layer compresses); {law!r} acts by impulses", field=f"{where}.law")
    bumper = Bumper(str(table["on"]), tuple(table["storeys"]), table["thickness"], table.get("compressible", 1.0), law, params)
    try:
        check_bumper(replace(rule, bumper=bumper), buildings, rest_gap)
    except InputError as exc:
        raise exc.located(field_prefix=where) from None
    return replace(bumper, thickness=float(bumper.thickness), compressible=float(bumper.compressible))


def _walls(tables: list, buildings: list[Building], analysis: Analysis, search: tuple) -> tuple[Wall, ...]:
    """The ``[[wall]]`` tables: retaining walls fixed to the ground (:mod:`pounding.framework.model.walls`)."""
    from pounding.contact.rules import wall_law
    from pounding.framework.model.registry import CONTACT_LAWS

    out, seen = [], {}
    for i, table in enumerate(tables):
        where = f"wall[{i}]"
        name = table["name"]
        if name in seen:
            raise InputError(f"wall name {name!r} is used twice (wall[{seen[name]}])", field=f"{where}.name")
        seen[name] = i
        face = np.asarray(table["face"], dtype=float)
        if "contact" in table:
            law, params = _own_law(table["contact"], analysis, f"{where}.contact", search)
        else:
            law, params = None, {}
        wall = Wall(name, face, float(table["top"]), law, params)
        try:
            check_wall(wall, buildings)
        except InputError as exc:
            raise exc.located(field_prefix=where) from None
        out.append(wall)
    scene_like = Scene((), None, analysis)
    default = CONTACT_LAWS.get(analysis.contact, search=search)(**analysis.contact_params)
    for i, wall in enumerate(out):
        try:
            wall_law(scene_like, wall, default)
        except ValueError as exc:
            raise InputError(str(exc).removeprefix(f"wall {wall.name!r}: "), field=f"wall[{i}].contact") from None
    return tuple(out)


# --------------------------------------------------------------------------- entry point
def parse_scene(data: Mapping, *, source: Path | None = None) -> Scene:
    """Validate a parsed TOML document and build the Scene (errors carry no file; see load_scene)."""
    from pounding.io.records import first_period_of_taller, load_ground_motion

    problems = scene_problems(data)
    if problems:
        raise problems[0].error()
    buildings = [_building(t, i) for i, t in enumerate(data["building"])]
    from pounding.framework.model.assembly import check_stable

    for i, b in enumerate(buildings):
        check_stable(b, field=f"building[{i}].element")
    names = [b.name for b in buildings]
    for i, nm in enumerate(names):
        if nm in names[:i]:
            raise InputError(f"building name {nm!r} is used twice", field=f"building[{i}].name")
    _check_apart_at_rest(buildings)
    base_dir = source.parent if source is not None else Path.cwd()
    gm = load_ground_motion(dict(data.get("ground_motion", {"record": "elcentro"})), base_dir=base_dir,
                            file=str(source) if source else None, default_period=lambda: first_period_of_taller(buildings))
    # a plugin named "module:Class" may live beside the scene file
    search = (base_dir,)
    analysis = _analysis(data.get("analysis", {}), search)
    if analysis.dt is not None and analysis.duration is not None and analysis.dt > analysis.duration:
        raise InputError(f"dt ({analysis.dt} s) is longer than the duration ({analysis.duration} s)", field="analysis.dt")
    contacts = _contact_rules(data.get("contact", []), buildings, analysis, search)
    from pounding.io.scene_links import parse_links

    links = parse_links(data.get("link", []), buildings)
    walls = _walls(data.get("wall", []), buildings, analysis, search)
    _one_impulse_law(data, contacts, walls, analysis, search)
    return Scene(tuple(buildings), gm, analysis, source, contacts, links=links, walls=walls)


def _one_impulse_law(data: Mapping, contacts: tuple, walls: tuple, analysis: Analysis, search: tuple) -> None:
    """Refuse the ``[[contact]]`` tables' and ``[[wall]]`` tables' own impulse laws when they cannot be one
    law (:func:`pounding.contact.rules.impulse_law_problem`, the rule the run applies): beside a force
    law ``[analysis] contact``, the first serves every pair that takes impulses."""
    from pounding.contact.rules import impulse_law_problem
    from pounding.framework.model.registry import CONTACT_LAWS

    def law(name, params):
        return CONTACT_LAWS.get(name, search=search)(**params)

    own = [(f"contact[{i}].law", law(r.law, r.params)) for i, (r, t) in enumerate(zip(contacts, data.get("contact", []))) if "law" in t]
    own += [(f"wall[{i}].contact", law(w.law, w.params)) for i, w in enumerate(walls) if w.law is not None]
    problem = impulse_law_problem(law(analysis.contact, analysis.contact_params), own)
    if problem is not None:
        raise InputError(problem[1], field=problem[0])


def load_scene(path: str | Path) -> Scene:
    """Read, validate and build a scene from a TOML file.

    Raises
    ------
    InputError
        Naming the file, the key path and what was expected.
    """
    path = Path(path)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise InputError(f"cannot read the scene file: {exc.strerror}", file=str(path)) from None
    try:
        data = tomllib.loads(raw.decode("utf-8"))
    except UnicodeDecodeError:
        raise InputError("the scene file is not UTF-8 text", file=str(path)) from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"not valid TOML: {exc}", file=str(path)) from None
    try:
        return parse_scene(data, source=path)
    except InputError as exc:
        raise InputError(exc.message, file=exc.file or str(path), field=exc.field) from None
