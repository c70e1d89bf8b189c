"""Bonds: the power connections between element ports.

A :class:`Bond` is a small immutable value, tail to head (the half-arrow
end, the direction of positive power).  It lives with the elements because
every element answers questions about its own bonds (port rules, causality).
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Bond"]


@dataclass(frozen=True)
class Bond:
    """A power bond from ``tail`` to ``head`` (the half-arrow end).

    ``number`` is the creation order within the graph that holds it (from 1).
    Endpoint names are paths: ``"Ra"`` or, for a sub-model port, ``"motor.shaft"``.
    Bonds are returned by :meth:`BondGraph.connect`.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("mass")
    >>> g.add(bg.Se("F"), bg.I("m"))
    >>> b = g.connect("F", "m")
    >>> b, str(b), b.other("F")
    (Bond(number=1, tail='F', head='m'), '1: F -> m', 'm')
    """

    number: int
    tail: str
    head: str

    def __str__(self) -> str:
        return f"{self.number}: {self.tail} -> {self.head}"

    def other(self, name: str) -> str:
        """The endpoint that is not ``name``."""
        return self.head if name == self.tail else self.tail
