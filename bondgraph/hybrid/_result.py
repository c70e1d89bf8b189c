"""The :class:`~bondgraph.numeric.result.TimeResponse` side of a switched run's result.

:class:`~bondgraph.hybrid.SwitchedResult` keeps its fields (``outputs``,
``stored``, ``inputs``, ``mode_index``, ``modes``, ``events``); this mixin
reads them as the one result protocol of every simulation: ``res["v"]``
searches the outputs, then the stored quantities (the states ``p_L``,
``q_C``), then the inputs, and the table has a ``mode`` column.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph import hybrid
>>> g = bg.BondGraph("rl")
>>> g.add(bg.Se("E"), bg.One("i"), bg.R("R"), bg.I("L"),
...       hybrid.ControlledSwitch("S", gate=1 - bg.t, on=True))
>>> for a, b in [("E", "i"), ("i", "R"), ("i", "L"), ("i", "S")]: _ = g.connect(a, b)
>>> sm = hybrid.SwitchedModel(g, outputs={"i": bg.flow("L")})
>>> res = bg.simulate(sm, {"R": 1, "L": 1}, (0, 2), u={"E": 1.0})
>>> res.names, float(res["E"][-1]), str(res.to_dataframe()["mode"].iloc[-1])
(('i', 'p_L', 'E'), 1.0, 'S off')
"""

from __future__ import annotations

from typing import Any

from ..numeric.result import TimeResponse

__all__ = ["SwitchedResponse"]


class SwitchedResponse(TimeResponse):
    """Mixin of :class:`~bondgraph.hybrid.SwitchedResult`: its signals by name and its modes."""

    __slots__ = ()

    def _signals(self):
        me: Any = self
        return (("output", me.outputs), ("state", me.stored), ("input", me.inputs))

    def _extra_columns(self) -> dict[str, Any]:
        me: Any = self
        names: Any = [str(m) for m in me.modes]
        return {"mode": [names[int(k)] for k in me.mode_index]}
