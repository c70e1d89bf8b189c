"""Private infrastructure shared by the stages (not part of the public API).

* :mod:`~bondgraph._support.sympify` -- the one strict conversion of user
  values to sympy (no string ever reaches ``sympify``);
* :mod:`~bondgraph._support.labels` -- LaTeX and python-control names;
* :mod:`~bondgraph._support.files` -- atomic writes, strict JSON and TOML
  readers (parameter, operating-point and study files);
* :mod:`~bondgraph._support.gcpause` -- the garbage collector paused while
  large acyclic results are built;
* :mod:`~bondgraph._support.moved` -- the old module paths of the package,
  served with a :class:`DeprecationWarning`.
"""
