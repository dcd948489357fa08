"""Hypothesis strategies for random valid scenes, the test profiles, and the checkers they share.

Profiles (no ``[tool.hypothesis]`` table anywhere; chosen here on import):

* ``ci``  - ``derandomize=True`` (a fixed seed per test), no example database, modest
  ``max_examples``; selected when the environment variable ``CI`` is set;
* ``dev`` - ten times the examples, random seeds, the local database.

``HYPOTHESIS_PROFILE`` overrides the choice. Tests scale their own example counts with
:func:`examples` so the ratio between cheap and expensive properties is kept in both.

Scene generation
----------------
Every scene is the TOML-like dict that :func:`pounding.io.scene.parse_scene` takes.
Slabs are *star-shaped* polygons: vertices at strictly increasing angles around a centre
with every angular gap below pi, which makes the polygon simple and star-shaped about the
centre (convex when all radii are equal, generally not otherwise), then rotated. Elements
(frames and shear walls) join two points ``c + t (v_i - c)`` with ``t < 1``, which lie on the
segment from the centre to a vertex and hence inside the slab. The second building is put
along a random plan direction and slid towards the first by conservative advancement
(shift by the current gap minus the target) until the rest gap equals the target, so gaps
from exactly touching to metres are all reached. A generated dict that the package rejects
with ``InputError`` is a generator mistake: :func:`parse_or_reject` counts it (by reason,
in :data:`REJECTED`) and filters it with ``assume``.
"""

from __future__ import annotations

import math
import os
from collections import Counter
from dataclasses import dataclass, field

import numpy as np
from hypothesis import HealthCheck, assume, event, settings
from hypothesis import strategies as st

from pounding.contact.geometry import ccw, signed_gap
from pounding.errors import InputError

# --------------------------------------------------------------------------- profiles
settings.register_profile(
    "ci",
    max_examples=40,
    derandomize=True,
    database=None,
    deadline=None,
    print_blob=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
settings.register_profile(
    "dev",
    max_examples=400,
    deadline=None,
    print_blob=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
# The suite gives the same verdict on every machine: `make test` runs the derandomized "ci"
# profile (fixed examples, no example database). "dev" (random seeds, 10x the examples, a local
# database that replays failures) is exploration, asked for by HYPOTHESIS_PROFILE=dev.
PROFILE = os.environ.get("HYPOTHESIS_PROFILE", "ci")
settings.load_profile(PROFILE)


def examples(weight: float = 1.0) -> int:
    """max_examples for a test: ``weight`` times the loaded profile's default (at least 3)."""
    return max(3, int(round(settings.default.max_examples * weight)))


# --------------------------------------------------------------------------- bookkeeping
#: Generated scenes the package rejected, by the first words of the reason.
REJECTED: Counter = Counter()
#: Generated scenes that parsed.
ACCEPTED: Counter = Counter()


def parse_or_reject(data: dict, what: str = "scene"):
    """parse_scene(data), or count the InputError and reject the example with ``assume``."""
    from pounding.io.scene import parse_scene

    try:
        sc = parse_scene(data)
    except InputError as exc:
        reason = f"{what}: {exc.field}: {' '.join(exc.message.split()[:6])}"
        REJECTED[reason] += 1
        event(f"rejected by parse_scene ({what})")
        assume(False)
        raise AssertionError("unreachable")  # pragma: no cover
    ACCEPTED[what] += 1
    return sc


def rejection_rate(what: str | None = None) -> tuple[int, int]:
    rej = sum(v for k, v in REJECTED.items() if what is None or k.startswith(what + ":"))
    acc = sum(v for k, v in ACCEPTED.items() if what is None or k == what)
    return rej, acc


# --------------------------------------------------------------------------- numbers
def log_uniform(lo: float, hi: float):
    return st.floats(math.log10(lo), math.log10(hi)).map(lambda e: float(10.0**e))


# --------------------------------------------------------------------------- polygons
@st.composite
def star_polygons(draw, size=None):
    """(vertices (k, 2) ccw, centre (2,)) of a random simple polygon around the origin.

    kind: "rectangle" (rotated), "convex" (vertices on a circle) or "star" (radii 0.45-1 of
    the size, convex or not). Angular gaps are kept in [0.2, pi - 0.2] rad so no three
    consecutive vertices are near collinear by construction of the angles alone.
    """
    R = draw(st.floats(3.0, 14.0)) if size is None else size
    kind = draw(st.sampled_from(["rectangle", "convex", "star", "star"]))
    rot = draw(st.floats(0.0, 2.0 * math.pi))
    if kind == "rectangle":
        w, d = R, draw(st.floats(0.4, 1.2)) * R
        P = np.array([[-w / 2, -d / 2], [w / 2, -d / 2], [w / 2, d / 2], [-w / 2, d / 2]])
    else:
        k = draw(st.integers(3, 9))
        gaps = np.array(draw(st.lists(st.floats(0.2, math.pi - 0.2), min_size=k, max_size=k)))
        gaps = gaps / gaps.sum() * 2.0 * math.pi
        assume(np.all(gaps > 0.15) and np.all(gaps < math.pi - 0.15))
        ang = np.concatenate([[0.0], np.cumsum(gaps[:-1])])
        if kind == "convex":
            r = np.full(k, R)
        else:
            r = R * np.array(draw(st.lists(st.floats(0.45, 1.0), min_size=k, max_size=k)))
        P = np.stack([r * np.cos(ang), r * np.sin(ang)], axis=1)
    c, s = math.cos(rot), math.sin(rot)
    P = P @ np.array([[c, s], [-s, c]])
    return ccw(P), np.zeros(2)


def interior_point(P, c, i, t):
    """c + t (P[i] - c): inside a polygon star-shaped about c for 0 <= t < 1."""
    return c + t * (P[i % len(P)] - c)


# --------------------------------------------------------------------------- elements
E_RC = 30e9


def _section(draw, lo=0.25, hi=0.8):
    b = draw(st.floats(lo, hi))
    return {"E": E_RC, "b": b, "h": draw(st.floats(lo, hi))}


@st.composite
def element_tables(draw, P, c, n_storeys, allow_walls=True):
    """3-6 frames / walls on random chords of the slab (inside it, see interior_point)."""
    k = len(P)
    n = draw(st.integers(3, 6))
    out = []
    for j in range(n):
        i0 = draw(st.integers(0, k - 1))
        i1 = draw(st.integers(0, k - 1))
        a = interior_point(P, c, i0, draw(st.floats(0.3, 0.95)))
        b = interior_point(P, c, i1, draw(st.floats(0.3, 0.95)))
        L = float(np.hypot(*(b - a)))
        assume(L > 0.5)
        kind = draw(st.sampled_from(["frame", "frame", "frame", "shear_wall"])) if allow_walls else "frame"
        # rounding the ends would move them off the slab; keep full precision
        if kind == "frame":
            ncol = draw(st.integers(2, 4))
            inner = sorted(draw(st.lists(st.floats(0.1, 0.9), min_size=ncol - 2, max_size=ncol - 2, unique=True)))
            cols = [0.0] + [x * L for x in inner] + [L]
            assume(all(q > p + 1e-3 for p, q in zip(cols, cols[1:])))
            table = {"type": "frame", "start": a.tolist(), "end": b.tolist(), "columns": cols,
                     "column": _section(draw), "beam": _section(draw, 0.3, 0.9)}
        else:
            table = {"type": "shear_wall", "start": a.tolist(), "end": b.tolist(),
                     "thickness": draw(st.floats(0.12, 0.4)), "E": E_RC, "nu": 0.2}
        # the first three span every storey (stability); later ones may stop lower
        if j >= 3 and n_storeys > 1 and draw(st.booleans()):
            table["storeys"] = draw(st.integers(1, n_storeys))
        out.append(table)
    return out


@st.composite
def damping_tables(draw, n_storeys):
    kind = draw(st.sampled_from(["rayleigh", "rayleigh", "modal", "stiffness", "default"]))
    ratio = draw(st.sampled_from([0.0, 0.02, 0.05, 0.1]))
    if kind == "default":
        return None
    if kind == "rayleigh":
        n = 3 * n_storeys
        i = draw(st.integers(1, min(n, 4)))
        j = draw(st.integers(1, n).filter(lambda x: x != i))
        return {"type": "rayleigh", "ratio": ratio, "modes": [i, j]}
    if kind == "modal":
        return {"type": "modal", "ratio": ratio}
    return {"type": "stiffness", "ratio": ratio, "modes": [1]}


def storey_counts():
    """1-20 storeys, mostly few (cost grows with storeys x steps x pairs)."""
    return st.one_of(st.integers(1, 3), st.integers(1, 3), st.integers(1, 6), st.integers(1, 20))


@st.composite
def building_tables(draw, name, P, c, n_storeys, heights=None):
    heights = heights or [3.2] * n_storeys
    table = {
        "name": name,
        "storey_heights": heights,
        "slab": P.tolist(),
        "element": draw(element_tables(P, c, n_storeys)),
    }
    if draw(st.booleans()):
        table["mass_per_area"] = draw(st.floats(300.0, 1500.0))
    else:
        table["mass"] = draw(st.floats(2e4, 4e5))
    if draw(st.integers(0, 3)) == 0:
        # eccentric mass: a centre of mass on a chord, inside the slab
        i = draw(st.integers(0, len(P) - 1))
        t = draw(st.floats(0.0, 0.5))
        table["centre_of_mass"] = [interior_point(P, c, i, t).tolist()] * n_storeys
    d = draw(damping_tables(n_storeys))
    if d is not None:
        table["damping"] = d
    return table


def place_at_gap(A, B, direction, gap, iters=200):
    """Translate B (far along ``direction`` from A) towards A until signed_gap(A, B) == gap.

    Conservative advancement: each shift is the current gap minus the target, which never
    overshoots because the gap is 1-Lipschitz in the translation. Returns (offset, final gap).
    """
    d = np.asarray(direction, float)
    d = d / np.hypot(*d)
    reach = float(np.max(np.hypot(*A.T)) + np.max(np.hypot(*B.T))) + 1.0
    off = d * (reach + gap)
    g = float(signed_gap(A, B + off))
    for _ in range(iters):
        step = g - gap
        if step <= 1e-12 * reach:
            break
        off = off - d * step
        g = float(signed_gap(A, B + off))
    return off, g


GAPS = st.one_of(
    st.just(0.0),
    st.sampled_from([1e-6, 1e-4, 1e-3]),
    log_uniform(1e-3, 0.2),
    st.floats(0.2, 3.0),
)


@st.composite
def integrators(draw):
    name = draw(st.sampled_from(["newmark", "newmark", "hht", "generalized_alpha", "central_difference", "exact", "exact"]))
    if name == "newmark":
        choice = draw(st.sampled_from(["average", "average", "linear", "damped"]))
        if choice == "average":
            return {"name": "newmark"}
        if choice == "linear":
            return {"name": "newmark", "preset": "linear"}
        gamma = draw(st.floats(0.5, 0.7))
        return {"name": "newmark", "gamma": gamma, "beta": 0.25 * (gamma + 0.5) ** 2}
    if name == "hht":
        return {"name": "hht", "alpha": draw(st.sampled_from([0.0, -0.05, -0.1, -1.0 / 3.0]))}
    if name == "generalized_alpha":
        return {"name": "generalized_alpha", "rho_inf": draw(st.sampled_from([0.0, 0.5, 0.8, 1.0]))}
    return {"name": name}


@st.composite
def contacts(draw):
    name = draw(st.sampled_from(["impulse", "impulse", "impulse", "penalty", "none"]))
    if name == "impulse":
        return {"name": "impulse", "locate": draw(st.sampled_from(["halving", "root"])),
                "tolerance": draw(st.sampled_from([1e-5, 1e-4, 1e-3])),
                "after_impact": draw(st.sampled_from(["keep", "equilibrium"]))}
    if name == "penalty":
        return {"name": "penalty", "stiffness": draw(log_uniform(1e7, 1e10)), "tolerance": 1e-4}
    return {"name": "none"}


RESTITUTIONS = st.one_of(st.sampled_from([0.0, 1.0]), st.floats(0.0, 1.0))


@dataclass
class Generated:
    """A generated scene dict with the knobs a test reads back."""

    data: dict
    gap: float
    notes: dict = field(default_factory=dict)


@st.composite
def scenes(draw, max_steps=1500, storeys=None, contact=None, integrator=None):
    """A random valid scene of two adjacent buildings (see the module docstring)."""
    PA, cA = draw(star_polygons())
    PB, cB = draw(star_polygons())
    storeys = storey_counts() if storeys is None else storeys
    n_a = draw(storeys)
    n_b = draw(st.one_of(st.just(n_a), storeys))
    h = draw(st.sampled_from([3.0, 3.2, 3.5]))
    heights_a = [h] * n_a
    # mostly common storey heights (a pair at every common level); sometimes a different first storey
    heights_b = [h] * n_b if draw(st.integers(0, 3)) else [h + draw(st.sampled_from([0.0, 0.4]))] + [h] * (n_b - 1)
    gap = draw(GAPS)
    theta = draw(st.floats(0.0, 2.0 * math.pi))
    off, g = place_at_gap(PA, PB, (math.cos(theta), math.sin(theta)), gap)
    assume(abs(g - gap) <= 1e-7 + 1e-6 * gap)
    PB = PB + off
    cB = cB + off
    A = draw(building_tables("a", PA, cA, n_a, heights_a))
    B = draw(building_tables("b", PB, cB, n_b, heights_b))
    dt = draw(log_uniform(1e-4, 0.04))
    duration = draw(st.floats(0.5, 3.0))
    duration = max(min(duration, max_steps * dt), 10 * dt)
    data = {
        "title": "generated",
        "building": [A, B],
        "ground_motion": {"record": "elcentro", "pga": draw(st.floats(0.05, 1.0)), "angle": draw(st.floats(0.0, 360.0))},
        "analysis": {
            "integrator": draw(integrators() if integrator is None else integrator),
            "dt": dt,
            "duration": duration,
            "contact": draw(contacts() if contact is None else contact),
            "restitution": draw(RESTITUTIONS),
            "output_every": 1,
        },
    }
    return Generated(data, gap, {"theta": theta, "storeys": (n_a, n_b)})


# --------------------------------------------------------------------------- TOML (for bug reports)
def to_toml(data: dict) -> str:
    """A minimal TOML writer for scene dicts (for minimal reproductions in reports)."""

    def val(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, (int, float, np.floating, np.integer)):
            return repr(float(v)) if isinstance(v, (float, np.floating)) else str(v)
        if isinstance(v, str):
            return '"' + v + '"'
        if isinstance(v, dict):
            return "{ " + ", ".join(f"{k} = {val(x)}" for k, x in v.items()) + " }"
        return "[" + ", ".join(val(x) for x in v) + "]"

    lines = []
    for k, v in data.items():
        if not isinstance(v, (dict, list)) or (isinstance(v, list) and v and not isinstance(v[0], dict)):
            lines.append(f"{k} = {val(v)}")
    for k, v in data.items():
        if isinstance(v, dict):
            lines.append(f"\n[{k}]")
            lines += [f"{kk} = {val(x)}" for kk, x in v.items()]
    for b in data.get("building", []):
        lines.append("\n[[building]]")
        for kk, x in b.items():
            if kk != "element":
                lines.append(f"{kk} = {val(x)}")
        for e in b.get("element", []):
            lines.append("  [[building.element]]")
            lines += [f"  {kk} = {val(x)}" for kk, x in e.items()]
    return "\n".join(lines) + "\n"


# =========================================================================== run-time checkers
# (shared by test_stress.py and test_hard_cases.py; they read a run physically, not through
# the driver's modal rows, so the modal bookkeeping is checked too)
from pounding.framework.engine.driver import MAX_EVENTS_PER_STEP, Driver  # noqa: E402

#: trial steps one located event may cost: <= 200 bisections + Brent's <= 100 iterations + a few
TRIALS_PER_EVENT = 320


class InstrumentedDriver(Driver):
    """A Driver that logs, per Python step, its located events, trial steps and impacts, and
    the modal state just before and after every contact_at call that applied an impulse."""

    def __init__(self, *a, **kw):
        super().__init__(*a, **kw)
        self.trials = 0
        self.step_log: list[tuple[int, int, int, int]] = []  # (k, located events, trials, impacts)
        self.impulse_log: list[dict] = []
        self.ever_sustained: set[int] = set()  # pairs ever held in sustained contact

    def trial(self, z, t, h):
        self.trials += 1
        return super().trial(z, t, h)

    def python_step(self, k):
        n0, t0, i0 = self.n_located, self.trials, len(self.impacts)
        super().python_step(k)
        self.ever_sustained |= self.sustained
        self.step_log.append((k, self.n_located - n0, self.trials - t0, len(self.impacts) - i0))

    def contact_at(self, t, pairs=None):
        q, v0, n0 = self.z[:, 0].copy(), self.z[:, 1].copy(), len(self.impacts)
        acted = super().contact_at(t, pairs)
        self.ever_sustained |= self.sustained
        if acted:
            self.impulse_log.append({"t": t, "q": q, "before": v0, "after": self.z[:, 1].copy(), "impacts": self.impacts[n0:]})
        return acted


def slab_states(model, x):
    """Physical (u, v, phi) or rates of every slab from a stacked modal vector: {(b, f): (3,)}."""
    out = {}
    for b, s in enumerate(model.systems):
        i0 = model.mode_start[b]
        X = (s.modes @ x[i0 : i0 + s.n_dof]).reshape(s.n_storeys, 3)
        for f in range(s.n_storeys):
            out[(b, f)] = X[f]
    return out


def momentum_residuals(model, ev) -> list[dict]:
    """Per slab pair that got impulses at one contact_at call: the change of its linear momentum
    sum m (u', v') and of its angular momentum about the origin sum J phi' + m (c x v) (c the
    current centre of mass), with their scales: sums of the magnitudes of the terms, m |v| and
    m |c| |v| + J |phi'|, of the jumps and of the state before (rounding of z' + w I is relative to
    the state); and the largest velocity jump of any slab outside those pairs."""
    x = slab_states(model, ev["q"])
    v0 = slab_states(model, ev["before"])
    dv = slab_states(model, ev["after"] - ev["before"])
    acted = sorted({imp.pair for imp in ev["impacts"]})
    out, touched = [], set()
    facades = getattr(model, "facades", {})

    def slabs_of(p):
        a, fa, b, fb, _ = model.pairs[p]
        keys = [(a, fa), (b, fb)]
        F = facades.get(p)
        if F is not None and F.storey > 0:  # a facade between floors: the impulse reaches the floor below too
            keys.append((b, F.storey - 1))
        return keys

    # pairs that share a slab at this instant (a facade and the slab pair below it, a floor between
    # two facades) exchange momentum through it: their momentum is checked together
    groups = []
    for p in acted:
        ks = set(slabs_of(p))
        joined = [g for g in groups if g[1] & ks]
        for g in joined:
            groups.remove(g)
        groups.append(([p] + [q for g in joined for q in g[0]], ks.union(*[g[1] for g in joined])))
    for members, keyset in groups:
        p = min(members)
        dp, dL, sp, sL, state_p, state_L = np.zeros(2), 0.0, 0.0, 0.0, 0.0, 0.0
        for q in members:
            F = facades.get(q)
            if F is not None and F.storey == 0:
                # below the first floor the ground takes the storey shape's N1 share of the impulse
                n1, _ = F.shape
                for imp in ev["impacts"]:
                    if imp.pair == q:
                        f = n1 * imp.impulse * np.asarray(imp.normal)
                        dp += f
                        dL += float(imp.point[0] * f[1] - imp.point[1] * f[0])
        keys = sorted(keyset)
        for key in keys:
            touched.add(key)
            s = model.systems[key[0]].slabs[key[1]]
            c = s.centre + x[key][:2]
            j = dv[key]
            orb = s.mass * (c[0] * j[1] - c[1] * j[0])
            spin = s.polar_inertia * j[2]
            dp += s.mass * j[:2]
            dL += orb + spin
            sp += s.mass * float(np.hypot(*j[:2]))
            sL += s.mass * float(np.hypot(*c)) * float(np.hypot(*j[:2])) + abs(spin)
            w = v0[key]
            state_p += s.mass * float(np.hypot(*w[:2]))
            state_L += s.mass * float(np.hypot(*c)) * float(np.hypot(*w[:2])) + abs(s.polar_inertia * w[2])
        out.append({"pair": p, "dp": float(np.hypot(*dp)), "dL": abs(dL), "scale_p": sp, "scale_L": sL,
                    "state_p": state_p, "state_L": state_L})
    others = [float(np.max(np.abs(dv[k][:2]))) for k in dv if k not in touched]
    jump = max((float(np.max(np.abs(dv[k][:2]))) for k in touched), default=0.0)
    vel = max(float(np.max(np.abs(v0[k][:2]))) for k in v0)
    return out, (max(others, default=0.0), jump, vel)


def step_end_gaps(result, model, pairs=None, tol=0.0):
    """Signed gap of every slab pair at every output step where it could be <= ``tol``.

    Returns {pair: (indices, gaps)}; a step is skipped when the rest gap minus the largest
    vertex displacements of both slabs is above ``tol`` (the displacement field of a slab is
    affine in the point, so its largest magnitude over the polygon is at a vertex).
    """
    out = {}
    facades = getattr(model, "facades", {})
    for p, (a, fa, b, fb, rest) in enumerate(result.pairs):
        if pairs is not None and p not in pairs:
            continue
        if p in facades:  # a slab against a facade between floors: the facade's own motion
            idx = np.arange(len(result.t))
            out[p] = (idx, np.array([model.pair_gap(result.q[k], p) for k in idx]))
            continue
        sa, sb = result.systems[a].slabs[fa], result.systems[b].slabs[fb]
        # the slabs' motion as the contact geometry takes it (the turn exact)
        da = result.contact_offsets(result.names[a], fa)
        db = result.contact_offsets(result.names[b], fb)
        bound = rest - np.max(np.hypot(da[..., 0], da[..., 1]), axis=1) - np.max(np.hypot(db[..., 0], db[..., 1]), axis=1)
        idx = np.flatnonzero(bound <= tol)
        gaps = np.array([signed_gap(sa.vertices + da[k], sb.vertices + db[k]) for k in idx])
        out[p] = (idx, gaps)
    return out


def events_bound(n_pairs: int) -> int:
    """Located events one grid step may take: the driver holds the pairs in sustained contact
    after MAX_EVENTS_PER_STEP; each pair can still be located once more before it is held."""
    return MAX_EVENTS_PER_STEP + 1 + n_pairs
