"""The share of one whole contact each contact point stands for, fixed by the slabs at rest.

A force law gives the force of one *contact*: two slabs pressed together at one storey
(:mod:`pounding.contact.pointwise`). Where two slabs meet face to face the geometry reports the
face's two ends as two points, each with its own penetration, so the law must be shared between
them, or a face pressed flat would carry twice the law. The share of each point is fixed in
advance from the rest geometry, never from which points press in a step:

* a *face* of a slab pair is a pair of facing parallel edges, one of each slab, at the pair's
  rest gap (:func:`pounding.contact.geometry.face_ends`); its two ends each stand for half of
  it, and the vertices of its two edges are the points that can end it;
* a point that ends a face carries 1/2 of the law at its own penetration: as an end of a
  face-to-face feature, or as a corner alone when the slabs have turned and the other end has
  lifted off; a vertex that ends c faces, struck alone, carries c/2;
* every other point (a corner that ends no face, a midpoint of crossing edges) carries the whole
  law.

So the force of every point is share * F(delta, delta', ...) with a share that does not change
while the point stays in contact: for an elastic law F(delta) the contact forces derive from the
potential sum_i share_i integral_0^delta_i F, and the contact creates no energy when one end of a
face lifts off (a share of 1/m over the m points pressing, the rule this replaces, jumped from 1/2
to 1 there). A face pressed flat at both ends still carries F(delta): 2 * F / 2.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from pounding.compiler import njit
from pounding.contact.geometry import face_ends
from pounding.framework.engine import pairs as pg

#: the ends of a face: each stands for this share of it
FACE_END_SHARE = 0.5


def rest_face_ends(geo) -> np.ndarray:
    """(P, 2, kmax) int64: how many rest faces each vertex of each pair's two slabs ends
    (:func:`pounding.contact.geometry.face_ends`), slab a in [:, 0], slab b in [:, 1], for the pair
    arrays ``geo`` (:class:`~pounding.framework.engine.bundles.PairArrays`; facade slabs included)."""
    P, kmax = geo.pa.shape[0], geo.verts.shape[1]
    out = np.zeros((P, 2, kmax), dtype=np.int64)
    for p in range(P):
        sa = int(geo.off[geo.pa[p, 0]] + geo.pa[p, 1])
        sb = int(geo.off[geo.pb[p, 0]] + geo.pb[p, 1])
        A, B = geo.verts[sa, : geo.nvert[sa]], geo.verts[sb, : geo.nvert[sb]]
        out[p, 0, : len(A)], out[p, 1, : len(B)] = face_ends(A, B, float(geo.rest[p]))
    return out


def rest_point_names(geo, ends: np.ndarray) -> np.ndarray:
    """(P, 2, kmax, 2) int64: the name (striking slab, vertex) of each vertex of each pair's two slabs
    as a contact point (``ContactState.point``): itself, except where a vertex of the second slab ends
    a face at the same place as a vertex of the first at rest (facades that end in line, the two
    corners facing each other across the rest gap), which one point of the face's end then names
    whichever of the two presses: the first slab's vertex. ``ends``: :func:`rest_face_ends`."""
    P, kmax = geo.pa.shape[0], geo.verts.shape[1]
    out = np.empty((P, 2, kmax, 2), dtype=np.int64)
    out[:, 0, :, 0], out[:, 1, :, 0] = 0, 1
    out[:, :, :, 1] = np.arange(kmax)
    for p in range(P):
        sa = int(geo.off[geo.pa[p, 0]] + geo.pa[p, 1])
        sb = int(geo.off[geo.pb[p, 0]] + geo.pb[p, 1])
        A, B = geo.verts[sa, : geo.nvert[sa]], geo.verts[sb, : geo.nvert[sb]]
        # facing corners are the rest gap apart, to the coordinates' rounding
        near = float(geo.rest[p]) + 1e-9 * (1.0 + float(max(np.abs(A).max(), np.abs(B).max())))
        for j in np.flatnonzero(ends[p, 1, : len(B)] > 0):
            d = np.hypot(*(A - B[j]).T)
            i = np.flatnonzero((ends[p, 0, : len(A)] > 0) & (d <= near))
            if i.size:
                out[p, 1, j] = (0, i[np.argmin(d[i])])
    return out


@njit
def point_shares(ends, pair, who, idx, face):
    """Share (m,) of one whole contact each of m points carries (see the module docstring).

    Parameters
    ----------
    ends : ndarray (P, 2, kmax) int64
        :func:`rest_face_ends` of the run's pairs.
    pair, who, idx, face : ndarray (m,) int64
        Each point's pair, striking slab (0: a, 1: b), vertex (-1: not a vertex) and face-to-face id
        (-1: a point feature), as :func:`pounding.framework.engine.pairs.struck_features` gives them.
    """
    m = pair.shape[0]
    share = np.ones(m)
    for j in range(m):
        count = ends[pair[j], who[j], idx[j]] if idx[j] >= 0 else 0
        if count > 0:
            # an end of a face-to-face feature stands for its end of that one face; a vertex struck
            # alone for its end of every face it ends
            share[j] = FACE_END_SHARE if face[j] >= 0 else FACE_END_SHARE * count
    return share


class SharedPoints(NamedTuple):
    """Touching points of slab pairs with the share of one contact each stands for (:func:`touching_with_shares`)."""

    pair: np.ndarray  #: (m,) int, each point's pair
    gap: np.ndarray  #: (m,) its gap [m] (negative: penetrating)
    W: np.ndarray  #: (m, n) its modal row
    Q: np.ndarray  #: (m, 2) the point [m]
    N: np.ndarray  #: (m, 2) the unit normal from slab a towards slab b
    share: np.ndarray  #: (m,) the share of one whole contact it stands for (:func:`point_shares`)
    #: (m, 3) int64, its identity: (pair, striking slab (0: a vertex of the pair's first, 1: of its second), vertex);
    #: None where no law of the run keeps a state by point (none asks it)
    point: np.ndarray | None

    def take(self, keep: np.ndarray) -> "SharedPoints":
        """The points where ``keep`` (m,) bool is True."""
        return SharedPoints(*(None if x is None else x[keep] for x in self))


def touching_with_shares(q: np.ndarray, plist: np.ndarray, tol: float, n: int, geo, ends: np.ndarray,
                         names: np.ndarray | None = None) -> SharedPoints:
    """Touching features of the pairs ``plist`` with every penetrating one found (``deep``), stacked,
    and their shares and names (:class:`SharedPoints`) for modal displacements q (n,), contact
    tolerance ``tol`` [m], the rest faces ``ends`` (:func:`rest_face_ends`) and the vertices' names
    ``names`` (:func:`rest_point_names`; None: the points are not named, ``point`` None)."""
    f = pg.struck_features(np.ascontiguousarray(q, dtype=float), plist, float(tol), True, n, geo)
    point = None
    if names is not None:
        point = np.stack([f.pair, f.who, f.idx], axis=1)
        vertex = f.idx >= 0
        point[vertex, 1:] = names[f.pair[vertex], f.who[vertex], f.idx[vertex]]
    return SharedPoints(f.pair, f.gap, f.W, f.Q, f.N, point_shares(ends, f.pair, f.who, f.idx, f.face), point)
