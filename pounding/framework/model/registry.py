"""One registry pattern for the plugin families.

A :class:`Registry` merges the built-in plugins with those that installed
packages announce through a Python entry-point group
(``pounding.elements``, ``pounding.integrators``, ``pounding.contact``,
``pounding.hysteresis``).
Entry points are read once, lazily, on the first lookup. A plugin is checked
when it is loaded (it must subclass the family's base class and carry a
``name``, and satisfy its base class's ``check_contract()`` when it has one), not in
the middle of a run. A broken plugin (it fails to import, is not a subclass, its
``name`` disagrees with its registration, or it breaks its family's contract) is
reported when it is looked up, as an :class:`~pounding.errors.InputError` naming it
and what is wrong (exit code 2 on the command line); the other plugins are unaffected.
Two plugins with one name give a warning.

Lookup accepts a registered name or the class itself, as
``scipy.integrate.solve_ivp(method=...)`` does, or ``"module:Class"``: a class
that is not installed as an entry point, imported from ``module`` (an importable
module, or a ``module.py`` in one of the folders given as ``search``, such as a
scene file's own folder) and checked like an installed one.
"""

from __future__ import annotations

import importlib
import warnings
from importlib.metadata import entry_points
from typing import Generic, TypeVar

from pounding.errors import InputError

T = TypeVar("T")


class Registry(Generic[T]):
    """Name -> plugin class, for one family.

    Parameters
    ----------
    group : str
        Entry-point group, e.g. ``"pounding.elements"``.
    base : str
        Dotted path of the base class every plugin must subclass
        (imported lazily so that building a registry imports nothing heavy).
    builtins : dict of str -> str
        Built-in plugins as ``name -> "module:Class"``; they are found even
        when the package is not installed (running from a source tree).
    kind : str
        Human name of the family, used in messages ("element type").
    """

    def __init__(self, group: str, base: str, builtins: dict[str, str], kind: str):
        self.group = group
        self._base_path = base
        self._builtins = dict(builtins)
        self.kind = kind
        self._targets: dict[str, str] | None = None
        self._loaded: dict[str, type] = {}

    # -- discovery ---------------------------------------------------------------
    def _discover(self) -> dict[str, str]:
        if self._targets is None:
            targets = dict(self._builtins)
            for ep in entry_points(group=self.group):
                if ep.name in targets and targets[ep.name] != ep.value:
                    warnings.warn(
                        f"{self.kind} {ep.name!r} is registered twice "
                        f"({targets[ep.name]} and {ep.value}); keeping {targets[ep.name]}",
                        stacklevel=3,
                    )
                    continue
                targets[ep.name] = ep.value
            self._targets = targets
        return self._targets

    def names(self) -> list[str]:
        """Sorted names of every plugin that can be loaded."""
        return sorted(self._discover())

    def builtin_names(self) -> list[str]:
        """Sorted names of the plugins that ship with pounding."""
        return sorted(self._builtins)

    def _base(self) -> type:
        module, _, cls = self._base_path.partition(":")
        return getattr(importlib.import_module(module), cls)

    def _load(self, name: str) -> type:
        if name not in self._loaded:
            target = self._discover()[name]
            module, _, attr = target.partition(":")
            try:
                obj = getattr(importlib.import_module(module), attr)
            except Exception as exc:  # a broken third-party plugin must not hide the others
                raise InputError(f"{self.kind} {name!r} could not be loaded from {target}: {exc}") from exc
            self._check(name, obj)
            self._loaded[name] = obj
        return self._loaded[name]

    def _check(self, name: str, obj: object) -> None:
        base = self._base()
        if not (isinstance(obj, type) and issubclass(obj, base)):
            raise InputError(f"{self.kind} {name!r} must be a subclass of {base.__qualname__}, got {obj!r}")
        if getattr(obj, "name", None) != name:
            raise InputError(
                f"{self.kind} registered as {name!r} declares name={getattr(obj, 'name', None)!r}; they must agree"
            )
        check = getattr(obj, "check_contract", None)
        if check is not None:
            try:
                check()
            except TypeError as exc:
                raise InputError(f"{self.kind} {name!r}: {exc}") from exc

    # -- lookup ------------------------------------------------------------------
    def get(self, name_or_class: str | type, *, field: str | None = None, search: tuple = ()) -> type:
        """The plugin class for a name, ``"module:Class"`` (imported, ``search``: folders to look
        for ``module.py`` in when it is not importable), or the class itself, checked.

        Raises
        ------
        InputError
            For an unknown name (the message lists the known ones), a ``module:Class`` that does
            not import or name a class of the family, or a class that breaks its contract.
        """
        if isinstance(name_or_class, type):
            self._check(getattr(name_or_class, "name", None), name_or_class)
            return name_or_class
        if isinstance(name_or_class, str) and ":" in name_or_class and name_or_class not in self._discover():
            return self._by_path(name_or_class, field, search)
        if not isinstance(name_or_class, str) or name_or_class not in self._discover():
            import difflib

            known = ", ".join(self.names())
            close = difflib.get_close_matches(str(name_or_class), self.names(), n=1, cutoff=0.6)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise InputError(f"unknown {self.kind} {name_or_class!r}{hint}; known: {known}", field=field)
        return self._load(name_or_class)

    def _by_path(self, target: str, field: str | None, search: tuple) -> type:
        """The class ``"module:Class"`` names, imported and checked (see :meth:`get`)."""
        module, _, attr = target.partition(":")
        if not (module and attr) or ":" in attr or not all(p.isidentifier() for p in module.split(".") + attr.split(".")):
            raise InputError(f"expected a {self.kind} name or 'module:Class' (a module path and a class name), got {target!r}",
                             field=field)
        try:
            obj = importlib.import_module(module) if _importable(module, search) else _import_from(module, search)
            for part in attr.split("."):
                obj = getattr(obj, part)
        except ImportError as exc:
            where = f" (looked in {', '.join(str(s) for s in search)} and on the Python path)" if search else ""
            raise InputError(f"{self.kind} {target!r}: cannot import module {module!r}{where}: {exc}", field=field) from None
        except AttributeError:
            raise InputError(f"{self.kind} {target!r}: module {module!r} has no {attr!r}", field=field) from None
        except Exception as exc:  # a module that fails while importing: say so, in one line
            raise InputError(f"{self.kind} {target!r}: importing module {module!r} failed: {type(exc).__name__}: {exc}",
                             field=field) from None
        base = self._base()
        if not (isinstance(obj, type) and issubclass(obj, base)):
            what = f"the class {obj.__qualname__}" if isinstance(obj, type) else f"a {type(obj).__name__}"
            raise InputError(f"{self.kind} {target!r} is {what}, not a subclass of {base.__qualname__}", field=field)
        try:
            self._check(getattr(obj, "name", None), obj)
        except InputError as exc:
            raise InputError(f"{target!r}: {exc.message}", field=field) from None
        return obj

    def __contains__(self, name: str) -> bool:
        return name in self._discover()


def _importable(module: str, search: tuple) -> bool:
    """Whether ``module`` imports from the Python path (else it is looked for in ``search``)."""
    import importlib.util

    if not search:
        return True
    try:
        return importlib.util.find_spec(module) is not None
    except (ImportError, ValueError):
        return False


def _import_from(module: str, search: tuple):
    """Import ``module`` (a top-level name) from ``module.py`` in the first of the folders ``search``
    holding one, registered in ``sys.modules`` under its name."""
    import importlib.util
    import sys
    from pathlib import Path

    if module in sys.modules:
        return sys.modules[module]
    for folder in search:
        path = Path(folder) / (module.replace(".", "/") + ".py")
        if path.is_file():
            spec = importlib.util.spec_from_file_location(module, path)
            mod = importlib.util.module_from_spec(spec)
            sys.modules[module] = mod
            try:
                spec.loader.exec_module(mod)
            except BaseException:
                del sys.modules[module]
                raise
            return mod
    raise ModuleNotFoundError(f"No module named {module!r}")


ELEMENTS: Registry = Registry(
    "pounding.elements",
    "pounding.elements.base:PlanarElement",
    {
        "frame": "pounding.elements.frame:Frame",
        "shear_wall": "pounding.elements.shear_wall:ShearWall",
        "storey_springs": "pounding.elements.storey_springs:StoreySprings",
    },
    "element type",
)

INTEGRATORS: Registry = Registry(
    "pounding.integrators",
    "pounding.solvers.base:Integrator",
    {
        "newmark": "pounding.solvers.newmark:Newmark",
        "hht": "pounding.solvers.hht:HHT",
        "generalized_alpha": "pounding.solvers.generalized_alpha:GeneralizedAlpha",
        "central_difference": "pounding.solvers.central_difference:CentralDifference",
        "exact": "pounding.solvers.exact:Exact",
    },
    "integrator",
)

CONTACT_LAWS: Registry = Registry(
    "pounding.contact",
    "pounding.contact.base:ContactLaw",
    {
        "impulse": "pounding.contact.impulse:Impulse",
        "penalty": "pounding.contact.penalty:Penalty",
        "facade_penalty": "pounding.contact.penalty:FacadePenalty",
        "kelvin": "pounding.contact.kelvin:Kelvin",
        "hertz": "pounding.contact.hertz:Hertz",
        "hertzdamp": "pounding.contact.hertzdamp:HertzDamp",
        "jankowski": "pounding.contact.jankowski:Jankowski",
        "rubber": "pounding.contact.rubber:Rubber",
        "material": "pounding.contact.material:MaterialContact",
        "none": "pounding.contact.none:NoContact",
    },
    "contact law",
)


def watches_contact(analysis) -> bool:
    """Whether the contact law of ``analysis`` (a scene's ``[analysis]``: its ``contact``, a name,
    ``module:Class`` or a class) watches slab pairs at all: False for a law that switches contact
    off (the ``none`` law, or any law declaring neither impulses at events nor forces with the
    step, :meth:`pounding.contact.base.ContactLaw.watches`). Asked of the law, never of its name."""
    return CONTACT_LAWS.get(analysis.contact, field="analysis.contact").watches()


HYSTERESIS: Registry = Registry(
    "pounding.hysteresis",
    "pounding.hysteresis.base:HysteresisLaw",
    {
        "bilinear": "pounding.hysteresis.bilinear:Bilinear",
        "bouc_wen": "pounding.hysteresis.bouc_wen:BoucWen",
        "friction_pendulum": "pounding.hysteresis.friction_pendulum:FrictionPendulum",
        "elastic": "pounding.hysteresis.elastic:Elastic",
        "viscous": "pounding.hysteresis.viscous:Viscous",
        "maxwell": "pounding.hysteresis.maxwell:Maxwell",
        "kelvin": "pounding.hysteresis.kelvin:Kelvin",
    },
    "hysteresis law",
)
