"""Test-session setup shared by the doctests in ``bondgraph/``, ``tests/`` and the notebooks.

CPython 3.11's ``linecache.checkcache()`` snapshots the cache's keys and then
indexes the cache with each; sympy's ``lambdify`` registers a finalizer that
removes its ``<lambdifygenerated-N>`` entry when the generated function is
collected, so a garbage collection inside that loop (doctest resets pdb, which
calls ``checkcache``, before every example) raised ``KeyError`` in a doctest
that had nothing to do with it.  The guard retries the check, which then skips
the entry already gone (Python 3.12 reads the entry with ``cache.get``).
"""

import linecache

_checkcache = linecache.checkcache


def _checkcache_tolerant(filename=None):
    for _ in range(5):
        try:
            return _checkcache(filename)
        except KeyError:        # an entry removed by a finalizer during the loop
            continue
    return None


linecache.checkcache = _checkcache_tolerant
