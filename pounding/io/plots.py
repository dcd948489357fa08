"""Figures of a run (PNG, matplotlib's Agg canvas; pyplot is never imported).

:func:`plot_all` writes, into one directory:

* ``plan.png`` - plan of the slabs with their vertex numbers (the numbers the
  impact log and the other figures use) and where the impacts happened;
* ``displacement_histories.png`` - displacement histories of chosen slab
  vertices; by default the x displacement of each corner of the lower
  building's common-storey slabs that faces the other building, with the
  response without pounding overlaid when a ``reference`` Result is given
  (the paper's Fig. 3);
* ``impact_timeline.png`` - time vs storey, one marker shape per striking
  (building, vertex), marker area proportional to the impulse;
* ``gap_histories.png`` - signed clear distance of every slab pair (common
  storey) over time, impacts marked;
* ``energy_balance.png`` - the final energy terms of the run as stacked bars
  per building with the balance error, above histories rebuilt from the output
  steps (kinetic + strain exactly; input and damping by the trapezoidal rule
  on the output grid; cumulative impact loss from the log);
* ``response_profiles.png`` - peak drift ratios, storey shears, overturning
  moments and floor accelerations over height, the reference overlaid
  (:mod:`pounding.io.profile_plots`).

Every function returns the paths it wrote. Storeys are 1-based, vertices
0-based in scene order, as in the impact log.
"""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

import numpy as np

from pounding.io.plot_style import COLOURS, MARKERS, _figure, _save
from pounding.framework.post.energy_account import energy_balance

def _bindex(result, building) -> int:
    return int(building) if isinstance(building, (int, np.integer)) else result.names.index(building)


# =============================================================================
# Choosing points
# =============================================================================


def _point_polygon_distance(p: np.ndarray, poly: np.ndarray) -> float:
    a = poly
    b = np.roll(poly, -1, axis=0)
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300), 0.0, 1.0)
    return float(np.min(np.hypot(*(a + t[:, None] * ab - p).T)))


def lower_building(result) -> int:
    """Index of the building whose top slab is lowest (the first on a tie)."""
    tops = [max(sl.elevation for sl in s.slabs) for s in result.systems]
    return int(np.argmin(tops))


def facing_vertices(slab, other, frac: float = 0.25) -> list[int]:
    """Vertices of ``slab`` that face ``other``: at most ``frac`` x the slab radius farther from it than the nearest."""
    d = np.array([_point_polygon_distance(v, np.asarray(other.vertices, float)) for v in np.asarray(slab.vertices, float)])
    return [int(i) for i in np.flatnonzero(d <= d.min() + frac * slab.radius)]


def pairs_of(result) -> list:
    """The run's slab pairs; for a run without contact (no pairs kept), the slabs at a common level."""
    if result.pairs:
        return list(result.pairs)
    from pounding.io.vtk import level_pairs

    return level_pairs(result.systems)


def default_points(result) -> list[tuple[str, int, int, str]]:
    """(building, storey 1-based, vertex, "x") of each common-storey corner of the lower building facing the other."""
    low = lower_building(result)
    out = []
    walls = getattr(result, "walls", {})
    for p, (a, fa, b, fb, _) in enumerate(pairs_of(result)):
        if low not in (a, b) or p in walls:  # (a wall pair's second slab is a wall)
            continue
        f, other = (fa, result.systems[b].slabs[fb]) if a == low else (fb, result.systems[a].slabs[fa])
        slab = result.systems[low].slabs[f]
        for v in facing_vertices(slab, other):
            key = (result.names[low], f + 1, v, "x")
            if key not in out:
                out.append(key)
    return sorted(out, key=lambda k: (-k[1], k[2]))


def vertex_history(result, building, storey: int, vertex: int, component: str = "x", velocity: bool = False) -> np.ndarray:
    """History (nt,) of one slab vertex's x or y displacement (or velocity) [m]."""
    name = result.names[_bindex(result, building)]
    c = {"x": 0, "y": 1}[component]
    return result.vertices(name, velocity=velocity)[:, storey - 1, vertex, c]


def _of_slab(events, result, b: int, storey: int) -> list:
    """The impacts or force-law contact episodes among ``events`` whose pair holds slab ``storey`` (1-based) of building b."""
    out = []
    for e in events:
        a, fa, bb, fb, _ = result.pairs[e.pair]
        if (a, fa) == (b, storey - 1) or (bb, fb) == (b, storey - 1):
            out.append(e)
    return out


# =============================================================================
# Displacement histories
# =============================================================================


def _draw_history(ax, result, building, storey, vertex, component, reference):
    b = _bindex(result, building)
    name = result.names[b]
    y = vertex_history(result, b, storey, vertex, component) * 1e3
    if reference is not None:
        yr = vertex_history(reference, name, storey, vertex, component) * 1e3
        ax.plot(reference.t, yr, color="0.55", lw=1.0, ls="--", label="without pounding")
    ax.plot(result.t, y, color=COLOURS[0], lw=1.1, label="with pounding" if reference is not None else name)
    imps = _of_slab(result.impacts, result, b, storey)
    if imps:
        ti = np.array([i.time for i in imps])
        ax.plot(ti, np.interp(ti, result.t, y), "v", color=COLOURS[1], ms=4, label="impacts on this slab")
    for k, e in enumerate(_of_slab(result.contacts, result, b, storey)):  # a force law's contacts last: shaded spans
        ax.axvspan(e.start, e.end, color=COLOURS[1], alpha=0.25, lw=0, label="force contacts on this slab" if k == 0 else None)
    vx, vy = result.systems[b].slabs[storey - 1].vertices[vertex]
    ax.set_title(f"{name}, storey {storey}, vertex {vertex} ({vx:.2f}, {vy:.2f}) m", fontsize=9)
    ax.set_ylabel(f"{component} displ. [mm]")
    ax.axhline(0.0, color="0.8", lw=0.6, zorder=0)
    ax.grid(True, lw=0.3, alpha=0.6)


def plot_corner_history(result, building, storey: int, vertex: int, reference=None, path="corner_history.png", *, component: str = "x") -> Path:
    """Displacement history of one slab vertex, with a reference run (no pounding) overlaid if given.

    Parameters
    ----------
    result : Result
    building : str or int
        Building name or index.
    storey : int
        1-based.
    vertex : int
        0-based index in the slab polygon (scene order).
    reference : Result, optional
        The same scene without pounding.
    path : path
        PNG to write.
    component : {"x", "y"}
    """
    fig = _figure(8.0, 3.2)
    ax = fig.add_subplot(1, 1, 1)
    _draw_history(ax, result, building, storey, vertex, component, reference)
    ax.set_xlabel("time [s]")
    ax.legend(fontsize=8, loc="upper right")
    return _save(fig, path)


def shaking_components(result) -> tuple[str, ...]:
    """The displacement components worth plotting for the run's shaking direction: ("x",) along x,
    ("y",) along y, both otherwise."""
    angle = float((result.ground_motion or {}).get("angle", 0.0)) % 180.0
    if angle == 0.0:
        return ("x",)
    if angle == 90.0:
        return ("y",)
    return ("x", "y")


def plot_displacement_histories(result, path, *, points: Sequence | None = None, reference=None) -> Path:
    """One row per point (building, storey 1-based, vertex[, "x"|"y"]); default :func:`default_points`.

    Points given without a component, and the default points, are drawn in the
    components of the shaking (:func:`shaking_components`): x and y side by side
    when the ground motion is not along x or y.
    """
    comps = shaking_components(result)
    raw = list(points) if points is not None else [p[:3] for p in default_points(result)]
    if not raw:  # no pairs: the roof corners of the first building
        s = result.systems[0]
        raw = [(result.names[0], s.n_storeys, v) for v in range(len(s.slabs[-1].vertices))]
    rows = [[tuple(p)] if len(p) == 4 else [tuple(p) + (c,) for c in comps] for p in raw]
    ncol = max(len(r) for r in rows)
    fig = _figure(8.5 if ncol == 1 else 13.0, 1.0 + 2.2 * len(rows))
    axes = fig.subplots(len(rows), ncol, sharex=True, squeeze=False)
    for i, row in enumerate(rows):
        for j in range(ncol):
            if j >= len(row):
                axes[i, j].set_visible(False)
                continue
            bld, storey, vertex, comp = row[j]
            _draw_history(axes[i, j], result, bld, int(storey), int(vertex), comp, reference)
    axes[0, 0].legend(fontsize=8, loc="upper right")
    for ax in axes[-1]:
        ax.set_xlabel("time [s]")
    if ncol > 1:
        fig.suptitle(f"Shaking at {float(result.ground_motion.get('angle', 0.0)):g} deg from x: both displacement components", fontsize=10)
    return _save(fig, path)


# =============================================================================
# Impacts and gaps
# =============================================================================


def _plot_force_contacts(ax, result, contacts: list) -> None:
    """A force law's contact episodes on the impact timeline: a bar from start to end at the pair's
    storey, a marker at the start with area ~ impulse, one colour per pair of buildings."""
    groups: dict = {}
    for e in contacts:
        a, _, b, _, _ = result.pairs[e.pair]
        groups.setdefault((result.names[a], result.second_body(e.pair)[0]), []).append(e)
    imax = max(e.impulse for e in contacts) or 1.0
    for g, (key, eps) in enumerate(sorted(groups.items())):
        colour = COLOURS[(g + 3) % len(COLOURS)]
        y = [result.impact_storey(e) - 0.15 for e in eps]
        ax.hlines(y, [e.start for e in eps], [max(e.end, e.start + 1e-3 * float(result.t[-1])) for e in eps], color=colour, lw=3.0)
        ax.scatter([e.start for e in eps], y, s=[15 + 300 * e.impulse / imax for e in eps], marker="s", color=colour, alpha=0.7,
                   edgecolors="k", linewidths=0.4, label=f"{key[0]} <-> {key[1]} (contact by forces)")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.text(0.99, 0.10, f"{len(contacts)} contact{'' if len(contacts) == 1 else 's'} by forces (bars: start to end), "
            f"largest force {max(e.peak_force for e in contacts) / 1e3:.3g} kN, largest impulse {imax / 1e3:.3g} kN s",
            ha="right", va="bottom", transform=ax.transAxes, fontsize=8, color="0.3")


def plot_impact_timeline(result, path) -> Path:
    """Impacts: time vs storey (of the striking slab), a marker per striking (building, vertex) and
    what it struck (the other building's slab, or a storey's columns and walls between floors),
    area ~ impulse."""
    fig = _figure(9.0, 4.0)
    ax = fig.add_subplot(1, 1, 1)
    storeys = sorted({p[1] + 1 for p in pairs_of(result)}) or [1]
    contacts = list(getattr(result, "contacts", []))
    if contacts:
        _plot_force_contacts(ax, result, contacts)
    if not result.impacts and not contacts:
        ax.text(0.5, 0.5, "no impacts", ha="center", va="center", transform=ax.transAxes, fontsize=14, color="0.4")
    elif result.impacts:
        groups: dict = {}
        facades = getattr(result, "facades", {})
        for imp in result.impacts:
            # what was struck: the other building's slab, or its columns and walls between floors
            F = facades.get(imp.pair)
            key = (result.striking_building(imp), imp.vertex, result.struck_building(imp), -1 if F is None else F.storey + 1)
            groups.setdefault(key, []).append(imp)
        order = {name: i for i, name in enumerate(result.names)}  # (a wall, not a building: after them)
        keys = sorted(groups, key=lambda k: (order[k[0]], k[1], order.get(k[2], len(order)), k[2], k[3]))
        imax = max(i.impulse for i in result.impacts) or 1.0
        n = len(keys)
        for g, key in enumerate(keys):
            imps = groups[key]
            off = (g - (n - 1) / 2) * min(0.12, 0.6 / max(n, 1))
            t = [i.time for i in imps]
            y = [result.impact_storey(i) + off for i in imps]
            s = [15 + 300 * i.impulse / imax for i in imps]
            struck = f"{key[2]} slab" if key[3] < 0 else f"{key[2]} storey {key[3]} columns"
            struck = f"wall {key[2]}" if key[2] not in order else struck
            label = f"{key[0]} {'face' if key[1] < 0 else f'vertex {key[1]}'} -> {struck}"
            ax.scatter(t, y, s=s, marker=MARKERS[g % len(MARKERS)], color=COLOURS[g % len(COLOURS)], alpha=0.7, edgecolors="k", linewidths=0.4, label=label)
        leg = ax.legend(title="striking -> struck", fontsize=8, title_fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
        leg.get_frame().set_linewidth(0.4)
        for handle in getattr(leg, "legend_handles", getattr(leg, "legendHandles", [])):
            handle.set_sizes([40.0])
        ax.text(0.99, 0.02, f"{len(result.impacts)} impact{'' if len(result.impacts) == 1 else 's'}, largest impulse {imax / 1e3:.3g} kN s (marker area ~ impulse)", ha="right", va="bottom", transform=ax.transAxes, fontsize=8, color="0.3")
    ax.set_yticks(storeys)
    ax.set_ylim(min(storeys) - 0.6, max(storeys) + 0.6)
    ax.set_xlim(float(result.t[0]), float(result.t[-1]))
    ax.set_xlabel("time [s]")
    ax.set_ylabel("storey")
    ax.set_title("Impacts")
    ax.grid(True, lw=0.3, alpha=0.6)
    return _save(fig, path)


def plot_gap_histories(result, path, *, gaps: np.ndarray | None = None, tolerance: float | None = None) -> Path:
    """Signed clear distance between the slabs of every pair over time [mm], impacts marked."""
    from pounding.io.vtk import contact_tolerance, pair_gaps

    fig = _figure(9.0, 4.0)
    ax = fig.add_subplot(1, 1, 1)
    pairs = pairs_of(result)
    if not pairs:
        ax.text(0.5, 0.5, "no slab pairs at a common level", ha="center", va="center", transform=ax.transAxes, fontsize=14, color="0.4")
    else:
        g = pair_gaps(result, pairs) if gaps is None else gaps
        tol = contact_tolerance(result) if tolerance is None else tolerance
        for p, (a, fa, b, fb, rest) in enumerate(pairs):
            lab = f"storey {fa + 1}" if fa == fb else f"{result.names[a]} {fa + 1} / {result.names[b]} {fb + 1}"
            if p in getattr(result, "walls", {}):
                lab = f"{result.names[a]} {fa + 1} / wall {result.walls[p].name}"
            c = COLOURS[p % len(COLOURS)]
            ax.plot(result.t, g[:, p] * 1e3, lw=1.0, color=c, label=f"{lab} (rest {rest * 1e3:.4g} mm)")
            ti = np.array([i.time for i in result.impacts if i.pair == p]) if result.pairs else np.array([])
            if ti.size:
                ax.plot(ti, np.zeros_like(ti), "|", color=c, ms=10, mew=1.2)
        ax.axhline(0.0, color="k", lw=0.6)
        ax.axhspan(-tol * 1e3, tol * 1e3, color="0.85", zorder=0)
        # outside the axes, so that neither the legend nor the note covers a curve
        note = "ticks on 0: impacts\ngrey band: contact tolerance" if result.pairs else "no contact in this run:\nnegative = the slabs overlap"
        leg = ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), title=note, title_fontsize=7.5)
        leg.get_title().set_color("0.3")
        leg._legend_box.align = "left"
    ax.set_xlabel("time [s]")
    ax.set_ylabel("signed gap [mm]")
    ax.set_title("Clear distance between the slabs of each common storey")
    ax.grid(True, lw=0.3, alpha=0.6)
    return _save(fig, path)


# =============================================================================
# Energy
# =============================================================================


def energy_histories(result, scene=None) -> dict:
    """Energy terms over the output steps [J], summed over the buildings.

    ``kinetic_plus_strain`` is exact at the output steps (mass-normalised modes);
    ``damping`` and ``input`` (the latter only with ``scene``, for the ground
    motion) integrate the modal powers by the trapezoidal rule on the output
    grid; ``impact_loss`` is the cumulative loss of the logged impacts.
    """
    t = np.asarray(result.t, float)
    ks = np.zeros_like(t)
    pdamp = np.zeros_like(t)
    pin = np.zeros_like(t)
    ag = np.asarray(scene.ground_motion.samples(t), float).reshape(t.size, -1) if scene is not None else None  # (nt, c)
    for i, s in enumerate(result.systems):
        q, qd = result.modal(result.names[i]), result.modal(result.names[i], velocity=True)
        ks += 0.5 * np.sum(qd**2, axis=1) + 0.5 * np.sum((s.omega * q) ** 2, axis=1)
        pdamp += np.sum(2.0 * s.zeta * s.omega * qd**2, axis=1)
        if ag is not None:
            for j, d in enumerate(scene.ground_motion.directions()):
                pin += (qd @ s.participation(s.influence(d))) * (-ag[:, j])

    def cumtrapz(p):
        out = np.zeros_like(p)
        out[1:] = np.cumsum(0.5 * (p[1:] + p[:-1]) * np.diff(t))
        return out

    times = np.array([i.time for i in result.impacts])
    losses = np.array([i.energy_loss for i in result.impacts])
    order = np.argsort(times)
    cum = np.concatenate([[0.0], np.cumsum(losses[order])])
    loss = cum[np.searchsorted(times[order], t, side="right")] if times.size else np.zeros_like(t)
    out = {"t": t, "kinetic_plus_strain": ks, "damping": cumtrapz(pdamp), "impact_loss": loss}
    if ag is not None:
        out["input"] = cumtrapz(pin)
    return out


def plot_energy(result, path, *, scene=None) -> Path:
    """Energy balance: histories (top) and final totals per building with the balance error (bottom)."""
    fig = _figure(9.0, 7.0)
    ax1, ax2 = fig.subplots(2, 1, height_ratios=[1.0, 1.1])
    h = energy_histories(result, scene)
    kJ = 1e-3
    if "input" in h:
        ax1.plot(h["t"], h["input"] * kJ, color="k", lw=1.2, label="input (ground motion)")
    ax1.plot(h["t"], h["kinetic_plus_strain"] * kJ, color=COLOURS[0], lw=1.0, label="kinetic + strain")
    ax1.plot(h["t"], h["damping"] * kJ, color=COLOURS[2], lw=1.0, label="damping")
    ax1.plot(h["t"], h["impact_loss"] * kJ, color=COLOURS[1], lw=1.0, label="impact loss")
    if "input" in h:
        ax1.plot(h["t"], (h["kinetic_plus_strain"] + h["damping"] + h["impact_loss"]) * kJ, color="0.5", lw=0.8, ls=":", label="sum of the terms")
    ax1.set_xlabel("time [s]")
    ax1.set_ylabel("energy [kJ]")
    ax1.set_title("Energy over time (input, damping: trapezoidal on the output steps)", fontsize=10)
    ax1.legend(fontsize=8, loc="upper left")
    ax1.grid(True, lw=0.3, alpha=0.6)

    bal = energy_balance(result)
    e = result.energy
    terms = [("input", "input"), ("kinetic", "kinetic"), ("strain", "strain"), ("damping", "damping"), ("contact_forces", "contact-force work")]
    if any("links" in e[name] for name in result.names):  # the work of the links between slabs on each building
        terms.append(("links", "link work"))
    x = np.arange(len(terms) + 2)
    bottom = np.zeros(len(terms))
    for i, name in enumerate(result.names):
        vals = np.array([e[name][k] for k, _ in terms]) * kJ
        ax2.bar(x[: len(terms)], vals, bottom=bottom, color=COLOURS[i % len(COLOURS)], alpha=0.8, label=name, edgecolor="k", lw=0.3)
        bottom += vals
    ax2.bar([x[-2]], [bal["impact_loss"] * kJ], color="0.45", edgecolor="k", lw=0.3, label="impacts (pair)" if len(result.names) == 2 else "impacts (all buildings)")
    ax2.bar([x[-1]], [bal["error"] * kJ], color="#ffbf00", edgecolor="k", lw=0.3, label="balance error")
    labels = [lab for _, lab in terms] + ["impact loss", "error"]
    totals = list(bottom) + [bal["impact_loss"] * kJ, bal["error"] * kJ]
    for xi, v in zip(x, totals):
        ax2.annotate(f"{v:.4g}", (xi, v), xytext=(0, 2 if v >= 0 else -10), textcoords="offset points", ha="center", fontsize=8)
    ax2.set_xticks(x, labels, fontsize=8)
    ax2.axhline(0.0, color="k", lw=0.6)
    ax2.set_ylabel("energy at the end [kJ]")
    ax2.set_title(
        f"Balance: input + contact work - (kinetic + strain + damping + impact loss) = {bal['error'] * kJ:.4g} kJ "
        f"({100 * bal['relative_error']:.2f} % of the input)",
        fontsize=9,
    )
    ax2.legend(fontsize=8, loc="upper right")
    ax2.grid(True, axis="y", lw=0.3, alpha=0.6)
    return _save(fig, path)


# =============================================================================
# Plan
# =============================================================================


def plot_plan(result, path, *, scene=None) -> Path:
    """Plan of the slabs (every storey; vertex numbers on the slabs of the pairs), elements, retaining walls
    (with ``scene``) and impact points."""
    allv = np.vstack([np.asarray(sl.vertices, float) for s in result.systems for sl in s.slabs])
    span = np.ptp(allv, axis=0) + 1e-9
    # the legend sits right of the axes: about 6.3 of the 9 inches are left for the plan, drawn to scale
    fig = _figure(9.0, float(np.clip(1.4 + 6.3 * span[1] / span[0], 3.2, 9.0)))
    ax = fig.add_subplot(1, 1, 1)
    pairs = pairs_of(result)
    paired = {(a, fa) for a, fa, _, _, _ in pairs} | {(b, fb) for _, _, b, fb, _ in pairs}
    kinds: set = set()
    for i, s in enumerate(result.systems):
        c = COLOURS[i % len(COLOURS)]
        labelled = set()
        for f, slab in enumerate(s.slabs):
            v = np.asarray(slab.vertices, float)
            ax.fill(v[:, 0], v[:, 1], color=c, alpha=0.06)
            ax.plot(*np.vstack([v, v[:1]]).T, color=c, lw=0.8 + 0.4 * (f == s.n_storeys - 1), label=result.names[i] if f == 0 else None)
            if (i, f) in paired:
                for j, (x, y) in enumerate(v):
                    if (round(x, 6), round(y, 6), j) in labelled:
                        continue
                    labelled.add((round(x, 6), round(y, 6), j))
                    ax.annotate(str(j), (x, y), xytext=(4 if x >= slab.centre[0] else -10, 4 if y >= slab.centre[1] else -12), textcoords="offset points", fontsize=8, color=c)
        ax.plot(*s.slabs[0].centre, "+", color=c, ms=8)
        if scene is not None:
            try:
                bld = scene.building(result.names[i])
            except KeyError:
                bld = None
            for el in bld.elements if bld is not None else ():
                kinds.add(_draw_element_plan(ax, el, c))
    for w in getattr(scene, "walls", ()) if scene is not None else ():  # retaining walls: their face, as a thick line
        face = np.asarray(w.face, float)
        ax.plot(face[:, 0], face[:, 1], color="0.15", lw=3.0, solid_capstyle="butt", label=f"retaining wall {w.name!r} (top {w.top:g} m)")
        mid = 0.5 * (face[len(face) // 2 - 1] + face[len(face) // 2]) if len(face) % 2 == 0 else face[len(face) // 2]
        ax.annotate(w.name, mid, xytext=(5, 5), textcoords="offset points", fontsize=8, color="0.15")  # (two walls told apart)
    if result.impacts:
        pts = np.array([i.point for i in result.impacts])
        ax.scatter(pts[:, 0], pts[:, 1], s=18, color="k", marker="x", lw=0.8, label="impact points", zorder=5)
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles, labels = ax.get_legend_handles_labels()
    if "frame" in kinds:
        handles.append(Line2D([], [], color="0.3", lw=1.2, marker="s", ms=4, mfc="white"))
        labels.append("frame line, columns (squares)")
    if "wall" in kinds:
        handles.append(Patch(facecolor="0.3", edgecolor="k", hatch="////", lw=0.5))
        labels.append("shear wall (hatched bar)")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("Plan: slabs, elements, vertex numbers, centres of mass (+)")
    ax.legend(handles, labels, fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.grid(True, lw=0.3, alpha=0.6)
    ax.margins(0.08)
    return _save(fig, path)


def _draw_element_plan(ax, el, colour) -> str:
    """Draw one element in plan by what it is: a wall (its outline has panels) as a hatched bar, anything
    else as a line with its columns (the vertical lines of its outline) as squares. Returns "wall" or "frame"."""
    p0, p1 = (np.asarray(p, float) for p in el.plan_segment())
    shape = el.outline()
    d = np.asarray(el.direction, float)
    if shape.get("panels"):
        span = max(float(np.hypot(*(p1 - p0))), 1e-9)
        t = max(float(getattr(el, "thickness", 0.0)), 0.012 * span * 4, 0.15)  # visible however thin
        nrm = np.array([-d[1], d[0]]) * t / 2
        corners = np.array([p0 + nrm, p1 + nrm, p1 - nrm, p0 - nrm])
        ax.fill(corners[:, 0], corners[:, 1], facecolor=colour, edgecolor="k", hatch="////", lw=0.5, alpha=0.85, zorder=4)
        return "wall"
    ax.plot([p0[0], p1[0]], [p0[1], p1[1]], color=colour, lw=1.2, alpha=0.8, zorder=3)
    cols = sorted({round(s0, 9) for s0, z0, s1, z1 in shape.get("lines", []) if abs(s0 - s1) < 1e-9})
    if cols:
        pts = np.array([np.asarray(el.point, float) + s * d for s in cols])
        ax.plot(pts[:, 0], pts[:, 1], "s", color=colour, ms=4.5, mfc="white", mew=1.2, zorder=4)
    return "frame"


# =============================================================================
# Everything
# =============================================================================


def plot_all(scene, result, out_dir, *, reference=None, points: Sequence | None = None, springs: Sequence | None = None) -> list[Path]:
    """Write every figure of a run into ``out_dir`` (created); returns the PNG paths.

    Parameters
    ----------
    scene : Scene or None
        For the elements in the plan and the ground motion of the energy input history.
    result : Result
    out_dir : path
    reference : Result, optional
        The same scene without pounding, overlaid on the displacement histories.
    points : sequence of (building, storey 1-based, vertex[, "x" | "y"]), optional
        Points of the displacement histories; default :func:`default_points`.
    springs : sequence of (building, element 0-based, storey 1-based), optional
        Yielding springs whose hysteresis loops to draw; default: the most ductile one per building.
    """
    from pounding.io.profile_plots import plot_response_profiles

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = [
        plot_plan(result, out / "plan.png", scene=scene),
        plot_displacement_histories(result, out / "displacement_histories.png", points=points, reference=reference),
        plot_impact_timeline(result, out / "impact_timeline.png"),
        plot_gap_histories(result, out / "gap_histories.png"),
        plot_energy(result, out / "energy_balance.png", scene=scene),
        plot_response_profiles(result, out / "response_profiles.png", reference=reference),
    ]
    if getattr(result, "springs", None):  # yielding storey springs
        from pounding.io.spring_plots import plot_hysteresis, plot_spring_profiles

        paths.append(plot_hysteresis(result, out / "hysteresis_loops.png", springs=springs, reference=reference))
        paths.append(plot_spring_profiles(result, out / "spring_profiles.png", reference=reference))
    if getattr(result, "links", None):  # links between slabs: their loops
        from pounding.io.spring_plots import plot_link_loops

        paths.append(plot_link_loops(result, out / "link_loops.png", reference=reference))
    return paths
