"""Model files: a Python file with a ``model()`` function returning a definition.

A model is Python, so a model file is imported (executed) like any module:
only load files you trust.  The protocol is small::

    # models/dc_motor.py
    import bondgraph as bg
    from bondgraph.modelfile import ModelDefinition

    def model() -> ModelDefinition:
        g = bg.BondGraph("dc_motor")
        ...
        return ModelDefinition(graph=g, outputs={"omega": bg.flow("J")},
                               parameters={"Ra": 1.0, "La": 0.5e-3, ...},
                               description="DC motor, voltage to speed")

:func:`load_model` imports such a file by path and checks what it returns;
:meth:`ModelDefinition.derive` gives the :class:`~bondgraph.model.Model`.

Examples
--------
>>> import bondgraph as bg
>>> g = bg.BondGraph("rc")
>>> V, n = bg.Se("V"), bg.One("i")
>>> g.add(V, n, bg.R("R"), bg.C("C"))
>>> _ = g.connect(V, n); _ = g.connect(n, "R"); _ = g.connect(n, "C")
>>> d = ModelDefinition(g, {"vC": bg.effort("C")}, {"R": 1e3, "C": 1e-6})
>>> d.name, d.derive().state_names, dict(d.parameters)
('rc', ('q_C',), {'R': 1000.0, 'C': 1e-06})
"""

from __future__ import annotations

import hashlib
import importlib.util
import math
import numbers
import os
import reprlib
import stat
import sys
from dataclasses import dataclass, field, replace
from pathlib import Path
from types import MappingProxyType
from typing import Any, Callable, Mapping, Union

import sympy

from .model import derive as _derive
from .errors import BondGraphError
from .graph import BondGraph
from .model import Model

__all__ = ["ModelDefinition", "ModelFileError", "load_model"]

PathLike = Union[str, "os.PathLike[str]"]


class ModelFileError(BondGraphError, ValueError):
    """A model file is missing, is not Python, fails, or defines no model."""

    __module__ = "bondgraph"      # tracebacks name it where users import it: bondgraph.ModelFileError


@dataclass(frozen=True, eq=False)
class ModelDefinition:
    """What a model file's ``model()`` returns: a graph, outputs and default values.

    Parameters
    ----------
    graph : BondGraph
        The bond graph.  A copy is kept, so later edits of ``graph`` do not
        change the definition.
    outputs : mapping of str to sympy expression, optional
        Named outputs, as for :func:`bondgraph.derive`.
    parameters : mapping of str to float, optional
        Default numeric values keyed by parameter (symbol) name, such as
        ``"Ra"`` or ``"motor.Ra"``.  They need not cover every parameter.
        A value may carry units (a :mod:`sympy.physics.units` expression
        such as ``3 * u.newton / u.millimeter``): it is kept in SI
        (``3000.0``), the graph's dimensional check
        (:func:`bondgraph.library.units.check_units`) runs at once, and the
        model declares units (:attr:`units`).
    description : str, optional
        One line shown by the command line tool.
    domains : mapping, optional
        Domain seeds of the dimensional check (element name or bond number
        -> domain name, such as ``{"F": "translation"}``), for bonds whose
        domain no element or library component fixes.  Giving them also
        declares units.

    Raises
    ------
    ModelFileError
        If a field has the wrong type or a default value is not a finite real
        number.
    bondgraph.library.units.UnitError
        If the model declares units and a parameter's unit does not fit its
        element (naming the element, the parameter and both units).

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("mass")
    >>> F, v = bg.Se("F"), bg.One("v")
    >>> g.add(F, v, bg.I("m"))
    >>> _ = g.connect(F, v); _ = g.connect(v, "m")
    >>> d = ModelDefinition(g, {"v": bg.flow("m")}, {"m": 2})
    >>> d.derive().rhs, d.parameters["m"]
    ((F,), 2.0)
    """

    graph: BondGraph
    outputs: Mapping[str, sympy.Expr] = field(default_factory=dict)
    parameters: Mapping[str, float] = field(default_factory=dict)
    description: str = ""
    domains: Mapping[Union[str, int], str] = field(default_factory=dict)
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not isinstance(self.graph, BondGraph):
            raise ModelFileError(
                f"ModelDefinition.graph must be a bondgraph.BondGraph; got {type(self.graph).__name__}")
        if not isinstance(self.outputs, Mapping):
            raise ModelFileError(
                f"ModelDefinition.outputs must be a mapping of name to signal expression; "
                f"got {type(self.outputs).__name__}")
        if not isinstance(self.parameters, Mapping):
            raise ModelFileError(
                f"ModelDefinition.parameters must be a mapping of parameter name to number; "
                f"got {type(self.parameters).__name__}")
        if not isinstance(self.description, str):
            raise ModelFileError(
                f"ModelDefinition.description must be a str; got {type(self.description).__name__}")
        if not isinstance(self.domains, Mapping):
            raise ModelFileError(
                f"ModelDefinition.domains must be a mapping of element name or bond number to "
                f"domain name; got {type(self.domains).__name__}")
        values, given = {}, {}
        for key, value in self.parameters.items():
            if not isinstance(key, str):
                raise ModelFileError(
                    f"ModelDefinition.parameters: key {key!r} must be a parameter name (str)")
            if isinstance(value, sympy.Basic) and _carries_units(value):
                values[key] = _finite(_si(value, key), key)
            else:
                values[key] = _finite(value, key)
            given[key] = value
        object.__setattr__(self, "graph", self.graph.copy())
        object.__setattr__(self, "outputs", MappingProxyType(dict(self.outputs)))
        object.__setattr__(self, "parameters", MappingProxyType(values))
        object.__setattr__(self, "domains", MappingProxyType(dict(self.domains)))
        if self.domains or any(isinstance(v, sympy.Basic) and _carries_units(v)
                               for v in given.values()):
            from .library.units.check import check_units

            check_units(self.graph, given, domains=self.domains)     # a wrong unit fails here
            self._cache["given"] = given

    def __reduce__(self):
        # rebuilt from plain mappings (a MappingProxyType does not pickle), with the values
        # as given (units kept), so the checks run again on unpickling
        given = self._cache.get("given", self.parameters)
        return (ModelDefinition, (self.graph, dict(self.outputs), dict(given), self.description,
                                  dict(self.domains)))

    @property
    def name(self) -> str:
        """The graph's name."""
        return self.graph.name

    def derive(self) -> Model:
        """The derived :class:`~bondgraph.model.Model` (computed once, then cached).

        Examples
        --------
        >>> import bondgraph as bg
        >>> g = bg.BondGraph("m")
        >>> g.add(bg.Se("F"), bg.I("m")); _ = g.connect("F", "m")
        >>> d = ModelDefinition(g)
        >>> d.derive() is d.derive()
        True
        """
        if "model" not in self._cache:
            model = _derive(self.graph, outputs=dict(self.outputs))
            self._cache["model"] = replace(model, declared_parameters=tuple(self.parameters))
        return self._cache["model"]

    @property
    def switched(self):
        """The :class:`~bondgraph.hybrid.SwitchedModel` when the graph holds switches
        (:mod:`bondgraph.hybrid`), else None (computed once).

        A switched definition is switched in every command line command: the
        mode its graph is built in is only the initial mode.

        Examples
        --------
        >>> from bondgraph.hybrid import library
        >>> ModelDefinition(library.buck()).switched.switches
        ('S', 'D')
        >>> import bondgraph as bg
        >>> g = bg.BondGraph("m"); g.add(bg.Se("F"), bg.I("m")); _ = g.connect("F", "m")
        >>> ModelDefinition(g).switched is None
        True
        """
        if "switched" not in self._cache:
            found = None
            # a switch element's class is bondgraph.hybrid's: without that package loaded the
            # graph holds none (and checking loads no scipy, which its simulation needs)
            if "bondgraph.hybrid" in sys.modules and self._has_switches():
                from .hybrid import SwitchedModel

                found = SwitchedModel(self.graph, outputs=dict(self.outputs))
            self._cache["switched"] = found
        return self._cache["switched"]

    def _has_switches(self) -> bool:
        from .flatten import flatten
        from .hybrid.elements import SwitchElement

        return any(isinstance(el, SwitchElement) for el in flatten(self.graph).elements)

    @property
    def declares_units(self) -> bool:
        """True when a parameter carries units or :attr:`domains` are given."""
        return "given" in self._cache

    @property
    def unit_dimensions(self) -> Mapping[str, tuple]:
        """Signal or parameter name -> its dimension (SI base exponents), where known.

        The dimensions :func:`bondgraph.library.units.model_units` gives for the
        derived model's states, inputs, outputs and unit-carrying parameters;
        empty when the model declares no units.  Computed once.
        """
        if "dims" not in self._cache:
            dims: dict[str, tuple] = {}
            if self.declares_units:
                from .library.units.signals import model_units

                dims = model_units(self.derive(), self.graph, self._cache["given"],
                                   domains=self.domains)
            self._cache["dims"] = MappingProxyType(dims)
        return self._cache["dims"]

    @property
    def units(self) -> Mapping[str, str]:
        """Signal or parameter name -> its unit as text (SI, named where one matches).

        Empty when no parameter carries units and no :attr:`domains` are
        given; otherwise the units of every state, input and output the
        dimensional check can tell, and of each unit-carrying parameter.

        Examples
        --------
        >>> import bondgraph as bg, sympy.physics.units as u
        >>> g = bg.BondGraph("msd")
        >>> g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.C("k", stiffness="k"))
        >>> for t, h in [("F", "v"), ("v", "m"), ("v", "k")]: _ = g.connect(t, h)
        >>> d = ModelDefinition(g, {"x": bg.displacement("m")},
        ...                     {"m": 2 * u.kilogram, "k": 3 * u.newton / u.millimeter},
        ...                     domains={"F": "translation"})
        >>> d.parameters["k"], d.units["k"], d.units["x"], d.units["F"]
        (3000.0, 'newton/meter', 'meter', 'newton')
        >>> d.plant().units["p_m"]
        'kilogram*meter/second'
        >>> ModelDefinition(g, parameters={"m": 2.0}).units
        mappingproxy({})
        """
        if "texts" not in self._cache:
            texts: dict[str, str] = {}
            if self.unit_dimensions:          # the unit library only for a model with units
                from .library.units.signals import unit_text

                texts = {k: unit_text(d) for k, d in self.unit_dimensions.items()}
            self._cache["texts"] = MappingProxyType(texts)
        return self._cache["texts"]

    def plant(self, values: Mapping[str, float] | None = None):
        """Numeric plant at the default parameter values, overridden by ``values``.

        Defaults for parameters the derived model does not use are ignored
        (a model file may serve several variants); unknown names in
        ``values`` are an error.  ``values`` are numbers in SI units.  When
        the model declares units, the plant carries those of its states,
        inputs and outputs (:attr:`~bondgraph.numeric.NumericStateSpace.units`).

        Examples
        --------
        >>> import bondgraph as bg
        >>> g = bg.BondGraph("m")
        >>> g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b"))
        >>> for t, h in [("F", "v"), ("v", "m"), ("v", "b")]: _ = g.connect(t, h)
        >>> d = ModelDefinition(g, {"v": bg.flow("m")}, {"m": 2.0, "b": 4.0})
        >>> d.plant().A, d.plant({"b": 1.0}).A
        (array([[-2.]]), array([[-0.5]]))
        """
        from .numeric import compile_plant

        model = self.derive()
        if "compiled" not in self._cache:
            self._cache["compiled"] = compile_plant(model)
        used = {p.name for p in model.parameters}
        merged = {k: v for k, v in self.parameters.items() if k in used}
        merged.update(values or {})
        plant = self._cache["compiled"].plant(merged)
        if self.units:
            signals = {*plant.state_names, *plant.input_names, *plant.output_names}
            plant = plant.with_units({k: v for k, v in self.units.items() if k in signals})
        return plant

    def linearize(self, x0=None, u0=None, *, values: Mapping[str, float] | None = None,
                  equilibrium: bool = True, tol: float = 1e-9):
        """The numeric plant of the model linearized about ``(x0, u0)`` (or an
        :class:`~bondgraph.linear.operating.Equilibrium`), at the default values overridden
        by ``values``; it carries the model's units like :meth:`plant`.

        See :meth:`bondgraph.Model.linearize` for the arguments.

        Examples
        --------
        >>> import bondgraph as bg, sympy, sympy.physics.units as u
        >>> g = bg.BondGraph("pend")
        >>> g.add(bg.Se("T"), bg.One("w"), bg.I("J"),
        ...       bg.C("grav", law=sympy.Symbol("k") * sympy.sin(bg.q)))
        >>> for t, h in [("T", "w"), ("w", "J"), ("w", "grav")]: _ = g.connect(t, h)
        >>> d = ModelDefinition(g, {"a": bg.displacement("grav")},
        ...                     {"J": 2 * u.kilogram * u.meter**2, "k": 4 * u.newton * u.meter},
        ...                     domains={"T": "rotation"})
        >>> lin = d.linearize({"p_J": 0, "q_grav": 0}, {"T": 0})
        >>> lin.A.tolist(), lin.units["q_grav"], lin.units["T"]
        ([[0.0, -4.0], [0.5, 0.0]], '1 (dimensionless)', 'joule')
        """
        model = self.derive()
        used = {p.name for p in model.parameters}
        merged = {k: v for k, v in self.parameters.items() if k in used}
        merged.update(values or {})
        plant = model.linearize(x0, u0, values=merged, equilibrium=equilibrium, tol=tol)
        if self.units:
            signals = {*plant.state_names, *plant.input_names, *plant.output_names}
            plant = plant.with_units({k: v for k, v in self.units.items() if k in signals})
        return plant

    def to_control(self, values: Mapping[str, float] | None = None):
        """python-control ``StateSpace`` with labels, and ``units`` when the model declares
        them (see :meth:`plant` and :meth:`bondgraph.numeric.NumericStateSpace.to_control`)."""
        return self.plant(values).to_control()


def _finite(value: Any, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ModelFileError(
            f"default value of parameter {name!r} must be a finite real number; "
            f"got {type(value).__name__} {_short(value)}")
    try:
        out = float(value)
    except (OverflowError, TypeError, ValueError):
        raise ModelFileError(f"default value of parameter {name!r} must be a finite real number; "
                             f"got {_short(value)}, too large for a float") from None
    if not math.isfinite(out):
        raise ModelFileError(f"default value of parameter {name!r} must be finite; got {value!r}")
    return out


def _carries_units(value: sympy.Basic) -> bool:
    from sympy.physics.units import Quantity

    return bool(value.atoms(Quantity))


def _si(value: sympy.Basic, name: str) -> Any:
    """A unit-carrying value in SI (the dimensional check then tells whether it fits)."""
    from .library.units.check import UnitError, si_values

    try:
        return si_values({name: value})[name]
    except UnitError as exc:
        raise ModelFileError(f"default value of {exc}") from None


def _short(value: Any) -> str:
    try:
        return reprlib.repr(value)
    except Exception:   # a repr that fails, or an int too long for str()
        return f"<{type(value).__name__}>"


def load_model(path: PathLike) -> ModelDefinition:
    """Import a model file and return what its ``model()`` function builds.

    The file is executed as a Python module (the model *is* Python): load only
    files you trust.  While it runs, its directory is on ``sys.path`` so it may
    import helper modules next to it.

    Parameters
    ----------
    path : str or os.PathLike
        A ``.py`` file defining ``model()`` with no required arguments.

    Returns
    -------
    ModelDefinition

    Raises
    ------
    ModelFileError
        Naming the file: it does not exist, is not a ``.py`` file, raises
        (any exception, ``sys.exit`` with any code, ``raise SystemExit``)
        while being imported, has no callable ``model``, or ``model()`` fails
        the same ways or returns something other than a
        :class:`ModelDefinition`.
    KeyboardInterrupt
        When interrupted while the file's code runs (also a ``raise
        KeyboardInterrupt`` in the file); its message names the file.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> src = '''
    ... import bondgraph as bg
    ... from bondgraph.modelfile import ModelDefinition
    ... def model():
    ...     g = bg.BondGraph("spring")
    ...     g.add(bg.Sf("v"), bg.C("k"))
    ...     g.connect("v", "k")
    ...     return ModelDefinition(g, {"F": bg.effort("k")}, {"k": 0.5})
    ... '''
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d, "spring.py"); _ = p.write_text(src)
    ...     load_model(p).derive().rhs
    (v,)
    >>> load_model("no/such/model.py")
    Traceback (most recent call last):
    ...
    bondgraph.ModelFileError: model file 'no/such/model.py' does not exist
    """
    p = _model_path(path)
    module = _import(p)
    fn = _guarded(p, "while looking up model", lambda: getattr(module, "model", None))
    if fn is None:
        raise ModelFileError(
            f"model file '{p}' defines no function model(); it must define "
            "def model() -> bondgraph.modelfile.ModelDefinition")
    if not callable(fn):
        raise ModelFileError(f"model file '{p}': model is a {type(fn).__name__}, not a function")
    try:
        result = _guarded(p, "in model()", fn)
    except _ExitError:
        raise
    except BondGraphError as exc:
        raise ModelFileError(f"model file '{p}': model() failed: {_text(exc)}") from exc
    except Exception as exc:
        raise ModelFileError(
            f"model file '{p}': model() raised {type(exc).__name__}: {_text(exc)}") from exc
    if not isinstance(result, ModelDefinition):
        raise ModelFileError(
            f"model file '{p}': model() returned {type(result).__name__}; expected a "
            "bondgraph.modelfile.ModelDefinition(graph, outputs, parameters)")
    return result


def _model_path(path: Any) -> str:
    """The model file's path as the user gave it, checked to name a readable .py file."""
    from ._support.files import checked_path

    p = checked_path(path, "model file", ModelFileError)
    try:
        info = os.stat(p)
    except (FileNotFoundError, NotADirectoryError):
        raise ModelFileError(f"model file '{p}' does not exist") from None
    except OSError as exc:
        raise ModelFileError(f"cannot read model file '{p}': {exc.strerror or exc}") from None
    if not stat.S_ISREG(info.st_mode):
        raise ModelFileError(f"model file '{p}' is not a file")
    if Path(p).suffix != ".py":
        raise ModelFileError(f"model file '{p}' is not a Python file: expected a name ending in .py")
    return p


class _ExitError(ModelFileError):
    """The model file's code exited (``sys.exit``) or raised a non-``Exception``."""


def _guarded(p: str, doing: str, call: Callable[[], Any]) -> Any:
    """Run the model file's code: exits and interrupts are reported naming the file.

    ``SystemExit`` (``sys.exit`` with any code) and any other exception that
    is not an ``Exception`` become a :class:`ModelFileError` (``_ExitError``);
    ``KeyboardInterrupt`` stays one (an interrupt is not the file's error)
    with a message naming the file.  Other exceptions pass to the caller.
    """
    try:
        return call()
    except KeyboardInterrupt as exc:
        raise KeyboardInterrupt(f"model file '{p}' was interrupted {doing}") from exc
    except SystemExit as exc:
        raise _ExitError(f"model file '{p}' called sys.exit({_short(exc.code)}) {doing}; "
                             "a model file must not exit: define model() and return a "
                             "ModelDefinition") from None
    except Exception:
        raise
    except BaseException as exc:         # GeneratorExit, or a BaseException of the file's own
        raise _ExitError(f"model file '{p}' raised {type(exc).__name__} {doing}: "
                             f"{_text(exc)}") from None


def _text(exc: BaseException) -> str:
    """``str(exc)``, even when the exception's own ``__str__`` fails."""
    try:
        return str(exc)
    except Exception:
        return f"<{type(exc).__name__} whose message cannot be shown>"


def _import(p: str):
    resolved = Path(p).resolve()
    digest = hashlib.sha1(str(resolved).encode("utf-8", "surrogateescape")).hexdigest()[:10]
    modname = f"_bondgraph_model_{_identifier(Path(p).stem)}_{digest}"
    spec = importlib.util.spec_from_file_location(modname, resolved)
    if spec is None or spec.loader is None:  # pragma: no cover - .py files always have a loader
        raise ModelFileError(f"model file '{p}' cannot be imported")
    module = importlib.util.module_from_spec(spec)
    folder = str(resolved.parent)
    sys.path.insert(0, folder)
    sys.modules[modname] = module
    loader = spec.loader
    try:
        _guarded(p, "while being imported", lambda: loader.exec_module(module))
    except SyntaxError as exc:
        sys.modules.pop(modname, None)
        raise ModelFileError(
            f"model file '{p}' has a syntax error at line {exc.lineno}: {exc.msg}") from exc
    except _ExitError:
        sys.modules.pop(modname, None)
        raise
    except Exception as exc:
        sys.modules.pop(modname, None)
        raise ModelFileError(
            f"model file '{p}' raised {type(exc).__name__} while being imported: {_text(exc)}") from exc
    except BaseException:
        sys.modules.pop(modname, None)
        raise
    finally:
        try:
            sys.path.remove(folder)
        except ValueError:  # pragma: no cover - the model removed it itself
            pass
    return module


def _identifier(stem: str) -> str:
    out = "".join(c if c.isalnum() or c == "_" else "_" for c in stem)
    return out or "model"
