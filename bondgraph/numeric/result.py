"""What every simulation returns: time, signals by name, a table and a plot.

:class:`TimeResponse` is the one protocol of simulation results.
:func:`bondgraph.simulate` returns a
:class:`~bondgraph.numeric.SimulationResult` for a smooth or implicit model
and a :class:`~bondgraph.hybrid.SwitchedResult` for a switched one; both are
``TimeResponse`` objects, so the same code reads either:

* ``res.t``: the sample times;
* ``res["v"]``: the history of the output, state or input called ``v``
  (outputs first, then states, then inputs when names are shared);
* ``res.names``: every name that indexes;
* ``res.events``: the mode changes (empty for a smooth model);
* ``res.to_dataframe()``: a :class:`pandas.DataFrame` indexed by time
  (pandas is imported only here);
* ``res.plot(["v", "iL"])``: a time-series plot on matplotlib axes
  (matplotlib is imported only here).

Examples
--------
>>> import numpy as np, bondgraph as bg
>>> g = bg.BondGraph("mass")
>>> g.add(bg.Se("F"), bg.I("m")); _ = g.connect("F", "m")
>>> model = bg.derive(g, outputs={"v": bg.flow("m")})
>>> res = bg.simulate(model, {"m": 2.0}, (0.0, 1.0), u=[3.0], t_eval=[0.0, 0.5, 1.0])
>>> isinstance(res, TimeResponse), res.names, res.events
(True, ('v', 'p_m', 'F'), ())
>>> round(float(res.to_dataframe().loc[1.0, "v"]), 9)          # v(1) = F t / m
1.5
"""

from __future__ import annotations

from typing import Any, Iterable, Mapping, Optional, Sequence, Union

import numpy as np

__all__ = ["TimeResponse"]


class TimeResponse:
    """Base of the simulation results: the signals by name, a table and a plot.

    A subclass gives ``t`` (the sample times) and :meth:`_signals` (its
    signals by kind); everything else is here.
    """

    __slots__ = ()

    t: np.ndarray
    #: mode changes; empty for a model without switches
    events: tuple = ()

    def _signals(self) -> Sequence[tuple[str, Mapping[str, np.ndarray]]]:
        """``[("output", {name: history}), ("state", {...}), ("input", {...})]`` in search order."""
        raise NotImplementedError

    def _extra_columns(self) -> dict[str, Any]:
        """Further table columns that are no signal (a switched run's ``mode``)."""
        return {}

    # ------------------------------------------------------------ names
    @property
    def names(self) -> tuple[str, ...]:
        """Every signal name that indexes the result: outputs, then states, then inputs."""
        out: dict[str, None] = {}
        for _, signals in self._signals():
            out.update(dict.fromkeys(signals))
        return tuple(out)

    def __contains__(self, name: object) -> bool:
        return any(name in signals for _, signals in self._signals())

    def __getitem__(self, name: str) -> np.ndarray:
        """The history of the output, state or input called ``name`` (searched in that order)."""
        for _, signals in self._signals():
            if isinstance(name, str) and name in signals:
                return signals[name]
        listed = "; ".join(f"{kind}s: {', '.join(signals) or '-'}" for kind, signals in self._signals())
        raise KeyError(f"no output, state or input named {name!r}; {listed}")

    def _chosen(self, signals: Union[None, str, Iterable[str]]) -> list[str]:
        if signals is None:
            return list(self.names)
        chosen = [signals] if isinstance(signals, str) else list(signals)
        for name in chosen:
            self[name]          # a KeyError listing the valid names
        return chosen

    # ------------------------------------------------------------ table and plot
    def to_dataframe(self, signals: Union[None, str, Iterable[str]] = None):
        """A :class:`pandas.DataFrame`, one column per signal, indexed by time ``t``.

        Parameters
        ----------
        signals : str or iterable of str, optional
            The columns (default: every name of :attr:`names`); a switched
            run adds the column ``mode`` (the mode of each sample).

        Returns
        -------
        pandas.DataFrame

        Raises
        ------
        KeyError
            A name that is no signal of the result (the valid ones listed).
        """
        import pandas as pd

        data: dict[str, Any] = {name: np.asarray(self[name]) for name in self._chosen(signals)}
        data.update(self._extra_columns())
        return pd.DataFrame(data, index=pd.Index(np.asarray(self.t), name="t"))

    def plot(self, signals: Union[None, str, Iterable[str]] = None, *, ax: Any = None,
             title: Optional[str] = None):
        """Plot signals against time (one line each, a legend; events as dotted lines).

        Parameters
        ----------
        signals : str or iterable of str, optional
            What to plot (default: the outputs, or the states of a model
            without outputs).
        ax : matplotlib Axes, optional
            Where to draw; default a new figure's axes.
        title : str, optional

        Returns
        -------
        matplotlib.axes.Axes

        Examples
        --------
        >>> import bondgraph as bg
        >>> g = bg.BondGraph("mass")
        >>> g.add(bg.Se("F"), bg.I("m")); _ = g.connect("F", "m")
        >>> res = bg.simulate(bg.derive(g, outputs={"v": bg.flow("m")}), {"m": 2.0}, (0.0, 1.0),
        ...                   u=[3.0])
        >>> ax = res.plot("v")
        >>> [line.get_label() for line in ax.get_lines()]
        ['v']
        >>> import matplotlib.pyplot as plt; plt.close("all")
        """
        if signals is None:
            kinds = dict(self._signals())
            signals = list(kinds.get("output") or kinds.get("state") or ())
        chosen = self._chosen(signals)
        if ax is None:
            import matplotlib.pyplot as plt

            _, ax = plt.subplots(figsize=(7.0, 4.0))
        t = np.asarray(self.t)
        for name in chosen:
            ax.plot(t, np.asarray(self[name]), label=name)
        for k, ev in enumerate(self.events):
            ax.axvline(ev.time, color="0.6", linestyle=":", linewidth=0.8,
                       label="events" if k == 0 else None)
        ax.set_xlabel("t [s]")
        if chosen or self.events:
            ax.legend(loc="best")
        if title:
            ax.set_title(title)
        ax.grid(True, alpha=0.3)
        return ax

