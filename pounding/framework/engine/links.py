"""Links with laws inside the compiled stepping: a run's laws as one tuple of compiled updates.

A link is a kinematic row over the modal coordinates, u = G q: the relative displacement of two
bodies (two floors of a building, a floor and the ground) along a direction at a point, as
OpenSees' zero-length element places a uniaxial material between two nodes. Its *law* gives the
force r [N] from the deformation u [m], the rate v [m/s] and the law's committed state, with its
tangents, by the contract of :mod:`pounding.hysteresis.base` (trial into a buffer, commit by copy,
revert by not copying). The stepping (:mod:`pounding.framework.engine.spring_core`) knows no law: it takes
the run's laws as a tuple of their compiled ``update`` functions (:func:`law_tuple`) and every
link's index in that tuple, and calls a link's law through :func:`law_update`.

Why a tuple and ``literal_unroll``
----------------------------------
numba types a compiled function passed as an argument by the function itself, so the stepping is
compiled once per tuple of laws a run holds (one specialization per scene's set of laws, each law
inlined where it is called, as if it were written there), and a law is one module and one
registration: nothing is generated or rewritten. ``literal_unroll`` visits the tuple's members,
whatever their types, and calls the one whose position is the link's index. numba's first-class
function types (one type for every law of one signature) would compile the stepping once for all
laws, but call each law through a pointer, which cannot be inlined, for every link and Newton
iteration of every step. The compiled stepping is cached on disk under its argument types; the
identity numba gives a compiled function in a type is fixed from its module, name and source
(:func:`pounding.compiler._fix_identity`), so the cache is found again by the next process, and a
law whose source changed is compiled afresh.

With the compiler off (``NUMBA_DISABLE_JIT=1``, or no numba), ``literal_unroll`` is the identity
and the same functions run as plain Python.
"""

from __future__ import annotations

from pounding import compiler
from pounding.compiler import njit


def literal_unroll(container):
    """The tuple itself: a plain loop over the laws (the compiler is off; with it on, numba's own
    ``literal_unroll`` replaces this when numba is set up: :func:`_with_numba`)."""
    return container


class LawTuple(tuple):
    """The compiled updates of a run's laws, as the stepping takes them: a tuple whose numba type is
    worked out once (registered with numba by :func:`_with_numba`).

    numba types a plain tuple of compiled functions anew at every call from Python, through its
    first-class-function unification (``inspect.signature`` of every member): measured 320 us per
    call, six times the springs' whole Newton of a Python step. The driver's Python steps call the
    springs' solve thousands of times a run."""


def law_tuple(laws: tuple) -> LawTuple:
    """The compiled ``update`` of every law class in ``laws``, in order: the stepping's law argument."""
    return LawTuple(cls.update for cls in laws)


def _with_numba() -> None:
    """What the laws' tuple needs from numba, set up when numba is (not at this module's import: a
    run served by the extension module never imports numba): its ``literal_unroll`` in this module's
    globals, where the compiled stepping reads it, and the numba type of a :class:`LawTuple`."""
    from numba import literal_unroll as unroll
    from numba.extending import typeof_impl

    globals()["literal_unroll"] = unroll

    @typeof_impl.register(LawTuple)
    def _typeof_laws(val, c):
        # numba's own type of the same plain tuple, worked out once per LawTuple
        t = val.__dict__.get("numba_type")
        if t is None:
            t = val.__dict__["numba_type"] = typeof_impl(tuple(val), c)
        return t


if compiler.enabled():
    import warnings

    # numba says so of every compiled function passed as an argument (the laws' updates here); it
    # has typed and called them so since 0.49, and the tests check the stepping against closed
    # forms and OpenSees: not a message for a user of a run
    warnings.filterwarnings("ignore", message="First-class function type feature is experimental")
    compiler.on_activate(_with_numba)


@njit
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
