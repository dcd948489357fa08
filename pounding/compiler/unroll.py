"""Tuples of compiled functions as arguments of compiled code: a run's laws as plugins.

A compiled function that calls "the law of this link" or "the laws of this contact" takes the laws'
compiled kernels as a tuple and visits it with numba's ``literal_unroll``
(:mod:`pounding.framework.engine.links` for the links' laws, :mod:`pounding.contact.pointwise` for
the point laws of contact). numba types a compiled function passed as an argument by the function
itself, so the caller is compiled once per tuple of laws (each law a direct call, no function
pointer) and
a law is one module and one registration: nothing is generated or rewritten.

What this module gives such a module:

* :class:`LawTuple`, the tuple to pass (:func:`kernel_tuple`): its numba type is worked out once. numba types a plain
  tuple of compiled functions anew at every call from Python, through its first-class-function
  unification (``inspect.signature`` of every member): measured 320 us a call, more than a whole
  step's Newton of the links.
* :func:`unrolled_in`, called with the module's ``globals()``: the module's ``literal_unroll`` is
  the identity while the compiler is off (no numba, or ``NUMBA_DISABLE_JIT=1``: the same functions
  run as plain Python, visiting the tuple in a plain loop) and numba's own once numba is set up
  (:func:`pounding.compiler.on_activate`; not at import: a run served by the extension module never
  imports numba).
"""

from __future__ import annotations

_NAMESPACES: list[dict] = []
_HOOKED = [False]


def literal_unroll(container):
    """The tuple itself (the compiler is off: a plain loop over the laws)."""
    return container


class LawTuple(tuple):
    """Compiled kernels as compiled code takes them: a tuple whose numba type is worked out once
    per tuple (registered with numba by :func:`_with_numba`); build it with :func:`kernel_tuple`,
    which gives the same tuple for the same kernels, so a caller that builds it at every step does
    not pay for the typing at every step."""

    #: numba types it by the tuple itself (its kernels): :func:`pounding.compiler.prebuilt.dispatch_print`
    typed_by_identity = True


_TUPLES: dict[tuple, LawTuple] = {}


def kernel_tuple(kernels) -> LawTuple:
    """The one :class:`LawTuple` of these kernels, in this order (kept for the process: a run's
    laws are a handful of functions)."""
    key = tuple(kernels)
    out = _TUPLES.get(key)
    if out is None:
        out = _TUPLES[key] = LawTuple(key)
    return out


def unrolled_in(namespace: dict) -> None:
    """Give the module whose ``globals()`` is ``namespace`` a ``literal_unroll``: this module's
    identity now, numba's once numba is set up (at once if it already is)."""
    from pounding import compiler

    namespace["literal_unroll"] = literal_unroll
    _NAMESPACES.append(namespace)
    if not _HOOKED[0]:
        _HOOKED[0] = True
        if compiler.enabled():
            import warnings

            # numba says so of every compiled function passed as an argument (the laws' kernels); it has
            # typed and called them so since 0.49, and the tests check the laws against closed forms and
            # OpenSees: not a message for a user of a run
            warnings.filterwarnings("ignore", message="First-class function type feature is experimental")
        compiler.on_activate(_with_numba)
    elif compiler._active:
        _set_unroll()


def _set_unroll() -> None:
    from numba import literal_unroll as unroll

    for namespace in _NAMESPACES:
        namespace["literal_unroll"] = unroll


def _with_numba() -> None:
    """numba's ``literal_unroll`` in every registered module and the numba type of a :class:`LawTuple`."""
    from numba.extending import typeof_impl

    _set_unroll()

    @typeof_impl.register(LawTuple)
    def _typeof_laws(val, c):
        # numba's own type of the same plain tuple, worked out once per LawTuple
        t = val.__dict__.get("numba_type")
        if t is None:
            t = val.__dict__["numba_type"] = typeof_impl(tuple(val), c)
        return t
