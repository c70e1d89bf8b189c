"""Errors of parameter studies, and the optional packages they need (private).

The study modules import pandas, tqdm, SALib and dask only when a study
runs, so ``import bondgraph`` (and ``import bondgraph.study``) work without
the ``study`` extra; asking for a study without them raises
:class:`MissingDependencyError` naming the extra.

Examples
--------
>>> import sys
>>> saved = sys.modules.get("SALib")
>>> sys.modules["SALib"] = None          # as if SALib were not installed
>>> try:
...     require("SALib", "sensitivity()")
... except MissingDependencyError as exc:
...     print(exc)
sensitivity() needs the package 'SALib', which is not installed; install the study extra: pip install "bondgraph[study]"
>>> if saved is None: del sys.modules["SALib"]
... else: sys.modules["SALib"] = saved
"""

from __future__ import annotations

import importlib
from types import ModuleType

from ..errors import BondGraphError

__all__ = ["StudyError", "MissingDependencyError", "StudyWarning", "require"]

#: distribution names of the packages (pip) behind the modules
_DISTRIBUTIONS = {"pandas": "pandas", "tqdm": "tqdm", "SALib": "SALib", "distributed": "dask[distributed]",
                  "dask": "dask", "pyarrow": "pyarrow"}


class StudyError(BondGraphError, ValueError):
    """A parameter study cannot run as asked (a bad range, design, metric or executor),
    or its samples cannot give the result asked for."""


class MissingDependencyError(BondGraphError, ImportError):
    """A package of the ``study`` extra is not installed (``pip install "bondgraph[study]"``)."""


class StudyWarning(UserWarning):
    """Some samples of a study failed; they are listed in the ``error`` column."""


def require(module: str, what: str) -> ModuleType:
    """Import ``module``, or raise :class:`MissingDependencyError` saying ``what`` needs it."""
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        top = module.split(".")[0]
        raise MissingDependencyError(
            f"{what} needs the package "
            f"'{_DISTRIBUTIONS.get(top, top)}', which is not installed; install the study extra: "
            'pip install "bondgraph[study]"') from exc
