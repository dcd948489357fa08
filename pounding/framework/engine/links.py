"""Links with laws inside the compiled stepping: a run's laws as one tuple of compiled updates.

A link is a kinematic row over the modal coordinates, u = G q: the relative displacement of two
bodies (two floors of a building, a floor and the ground) along a direction at a point, as
OpenSees' zero-length element places a uniaxial material between two nodes. Its *law* gives the
force r [N] from the deformation u [m], the rate v [m/s] and the law's committed state, with its
tangents, by the contract of :mod:`pounding.hysteresis.base` (trial into a buffer, commit by copy,
revert by not copying). The stepping (:mod:`pounding.framework.engine.spring_core`) knows no law: it takes
the run's laws as a tuple of their compiled ``update`` functions (:func:`law_tuple`) and every
link's index in that tuple, and calls a link's law through :func:`law_update`.

Why a tuple
-----------
numba types a compiled function passed as an argument by the function itself, so the stepping is
compiled once per tuple of laws a run holds (one specialization per scene's set of laws, each law
a direct call that the compiler may inline), and a law is one module and one
registration: nothing is generated or rewritten (:mod:`pounding.compiler.unroll`: the tuple's type
worked out once, and ``literal_unroll``, which visits its members whatever their types and calls
the one whose position is the link's index). numba's first-class function types (one type for
every law of one signature) would compile the stepping once for all laws, but call each law
through a pointer, which is never inlined, for every link and Newton iteration of every step. The
compiled stepping is cached on disk under its argument types; the identity numba gives a compiled
function in a type is fixed from its module, name and source (:func:`pounding.compiler._fix_identity`),
so the cache is found again by the next process, and a law whose source changed is compiled afresh.

With the compiler off (``NUMBA_DISABLE_JIT=1``, or no numba), ``literal_unroll`` is the identity
and the same functions run as plain Python.
"""

from __future__ import annotations

from pounding.compiler import njit
from pounding.compiler.unroll import LawTuple, kernel_tuple, literal_unroll, unrolled_in  # noqa: F401 - literal_unroll: numba's once set up

unrolled_in(globals())  # this module's literal_unroll: numba's once numba is set up


def law_tuple(laws: tuple) -> LawTuple:
    """The compiled ``update`` of every law class in ``laws``, in order: the stepping's law argument."""
    return kernel_tuple(cls.update for cls in laws)


@njit(borrowed=True)
def law_update(laws, j, u, h, state, params, new_state, s):
    """Force [N] and tangent [N/m] of link s, whose law is ``laws[j]``, at the trial deformation u [m]
    reached over a step of h [s] from its committed state ``state[s]``.

    The rate the law sees is the mean over the step, v = (u - u_committed) / h [m/s] (the committed
    deformation is the common state slot 0), so the tangent of the step is dr/du + dr/dv / h: the
    law's own tangent and its damping tangent over h. A step of no length (an impact located at a
    step's very start) changes nothing: the trial is the committed state and force (a dashpot keeps
    its force: asked at v = 0 it would drop it), with the law's own tangent (the step's compliance
    is zero). Writes the trial state ``new_state[s]``.
    """
    v = (u - state[s, 0]) / h if h > 0.0 else 0.0
    r = 0.0
    kt = 0.0
    i = 0
    for update in literal_unroll(laws):
        if i == j:
            r, k, c = update(u, v, state, params, new_state, s)
            kt = k + c / h if h > 0.0 and c != 0.0 else k
        i += 1
    if h <= 0.0:
        for c in range(state.shape[1]):
            new_state[s, c] = state[s, c]
        r = state[s, 1]
    return r, kt
