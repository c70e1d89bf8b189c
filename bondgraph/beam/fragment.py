"""Modal bond-graph fragments: a beam (or hub + beam) as a reusable sub-model.

Each mode ``i`` is a 1-junction ``eta_i`` (modal velocity) carrying
``I:m_i`` (modal mass), ``C:k_i`` (modal stiffness, ``e = k_i q``) and, when
damped, ``R:c_i``.  A 0-junction ``hub`` (common root torque) feeds every mode
through ``TF:root_i``; the modal force is ``phi_i'(0) * tau`` and the root
rotation is ``sum phi_i'(0) eta_i'``, so with the TF convention
(``e1 = n e2``, ``f2 = n f1``, port 1 at the hub) the modulus is
``1/phi_i'(0)``.  The same holds at the tip (``TF:tip_i``, modulus
``1/phi_i(L)``) when a tip port is asked for.  A rigid-body mode (inertia
only) may be included; its root gain is 1 and its tip gain the lever arm.

The fragment is a :class:`~bondgraph.BondGraph` with ``Port('hub')`` (and
``Port('tip')``), so ``derive`` and transfer functions work on it unchanged.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.beam import modal_beam
>>> from bondgraph.beam.fragment import beam_fragment
>>> beam = modal_beam(1.0, 1.0, 1.0, 2, boundary="pinned-free")
>>> frag = beam_fragment(beam, name="link")
>>> frag.graph.ports
('hub',)
>>> sorted(frag.values)[:4]
['link.a_1', 'link.a_2', 'link.b_1', 'link.b_2']
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence, Union

import sympy

from ..elements import C, I, One, Port, R, TF, Zero
from ..graph import BondGraph
from ..signals import displacement
from .hub import HubBeamModes
from .modal import ModalBeam

__all__ = ["ModeData", "ModalFragment", "modal_fragment", "beam_fragment"]


@dataclass(frozen=True)
class ModeData:
    """Numbers of one mode: mass, stiffness, damping, root gain, tip gain.

    Input of :func:`modal_fragment`; the root gain is ``phi'(0)`` and the tip
    gain ``phi(L)``.

    Examples
    --------
    >>> md = ModeData(mass=1.0, stiffness=4.0, damping=0.1, root=0.5, tip=2.0)
    >>> frag = modal_fragment([md], name="b")
    >>> frag.values
    {'b.m_1': 1.0, 'b.k_1': 4.0, 'b.a_1': 0.5, 'b.c_1': 0.1, 'b.b_1': 2.0}
    """

    mass: float
    stiffness: float
    damping: float
    root: float
    tip: float


@dataclass(frozen=True)
class ModalFragment:
    """A modal bond-graph fragment and the values of its symbols.

    Attributes
    ----------
    graph : BondGraph
        Ports ``hub`` (and ``tip``).
    values : dict of str to float
        Numeric value of each modal symbol (``<name>.m_1``, ``<name>.a_1``, ...).
    n_modes : int
        Number of flexible modes.
    rigid : bool
        Whether the rigid-body mode ``m_0`` is included.
    length : float
        Lever arm of the rigid mode at the tip (``r + L``).

    Examples
    --------
    >>> from bondgraph.beam import modal_beam
    >>> frag = beam_fragment(modal_beam(1.0, 1.0, 1.0, 2, boundary="pinned-free"), name="link")
    >>> frag.name, frag.graph.ports, frag.n_modes, frag.rigid, frag.length
    ('link', ('hub',), 2, True, 1.0)
    >>> frag.symbol("k_1"), frag.tip_deflection(relative=True)
    (link.k_1, displacement[k_1]*(-1.0*link.a_1 + link.b_1) + displacement[k_2]*(-1.0*link.a_2 + link.b_2))
    """

    graph: BondGraph
    values: Mapping[str, float]
    n_modes: int
    rigid: bool
    length: float

    @property
    def name(self) -> str:
        return self.graph.name

    def symbol(self, local: str) -> sympy.Symbol:
        """The symbol of a modal quantity, e.g. ``symbol('a_1')``."""
        full = f"{self.name}.{local}"
        if full not in self.values:
            raise KeyError(f"fragment {self.name!r} has no quantity {local!r}; "
                           f"it has {', '.join(sorted(self.values))}")
        return _sym(full, local)

    def tip_deflection(self, prefix: str = "", *, relative: bool = False) -> sympy.Expr:
        """Tip deflection ``sum phi_i(L) eta_i`` as a signal expression.

        ``relative=True`` gives the deflection seen from the rotating hub
        (a hub-mounted camera): ``sum (phi_i(L) - (r+L) phi_i'(0)) eta_i``,
        in which the rigid-body mode cancels.  ``prefix`` is the sub-model
        path of this fragment in the model (e.g. ``'beam.'``).
        """
        p = prefix
        terms = []
        if self.rigid and not relative:
            terms.append(self.length * displacement(f"{p}m_0"))
        for i in range(1, self.n_modes + 1):
            b, a = self.symbol(f"b_{i}"), self.symbol(f"a_{i}")
            gain = b - self.length * a if relative else b
            terms.append(gain * displacement(f"{p}k_{i}"))
        return sympy.Add(*terms)


def _sym(full: str, local: str) -> sympy.Symbol:
    positive = local[0] in "mkc" or local == "J_0"
    return sympy.Symbol(full, positive=True) if positive else sympy.Symbol(full, real=True)


def modal_fragment(modes: Sequence[ModeData], *, name: str = "beam", rigid_inertia: float | None = None,
                   length: float = 0.0, tip_port: bool = False, hub_port: bool = True) -> ModalFragment:
    """Build the modal fragment from per-mode numbers (kept as named symbols).

    Parameters
    ----------
    modes : sequence of ModeData
    name : str
        Graph name; symbols are ``<name>.m_i``, ``<name>.k_i``, ``<name>.c_i``,
        ``<name>.a_i`` (root gain) and ``<name>.b_i`` (tip gain).
    rigid_inertia : float, optional
        Include a rigid-body mode ``I:m_0`` with this inertia.
    length : float
        Tip lever arm of the rigid mode (``r + L``).
    tip_port : bool
        Expose ``Port('tip')``.
    hub_port : bool
        Expose ``Port('hub')`` (False for a cantilever clamped to ground,
        whose modes have zero root slope).

    Examples
    --------
    >>> frag = modal_fragment([ModeData(1.0, 4.0, 0.0, 0.5, 2.0)], name="b")
    >>> [el.label() for el in frag.graph.elements][:4]
    ['Port:hub', '0:hub_j', '1:eta_1', 'I:m_1']
    """
    g = BondGraph(name)
    values: dict[str, float] = {}

    def sym(local: str, value: float) -> sympy.Symbol:
        values[f"{name}.{local}"] = float(value)
        return _sym(f"{name}.{local}", local)

    if not (hub_port or tip_port):
        raise ValueError(f"modal fragment {name!r}: expose at least one of the hub and tip ports")
    hub = None
    if hub_port:
        hub = Zero("hub_j")
        g.add(Port("hub"), hub)
        g.connect("hub", hub)
    tip = None
    if tip_port:
        tip = Zero("tip_j")
        g.add(Port("tip"), tip)
        g.connect("tip", tip)
    if rigid_inertia is not None:
        g.add(One("eta_0"), I("m_0", sym("m_0", rigid_inertia)))
        if hub is not None:
            g.connect(hub, "eta_0")
        g.connect("eta_0", "m_0")
        if tip is not None:
            g.add(TF("tip_0", 1 / sym("b_0", length)))
            g.connect(tip, "tip_0")
            g.connect("tip_0", "eta_0")
    for i, md in enumerate(modes, start=1):
        eta = One(f"eta_{i}")
        g.add(eta, I(f"m_{i}", sym(f"m_{i}", md.mass)),
              C(f"k_{i}", stiffness=sym(f"k_{i}", md.stiffness)))
        a = sym(f"a_{i}", md.root)
        if hub is not None:
            if md.root == 0:
                raise ValueError(f"modal fragment {name!r}: mode {i} has zero root gain; "
                                 "build it without a hub port (hub_port=False)")
            g.add(TF(f"root_{i}", 1 / a))
            g.connect(hub, f"root_{i}")
            g.connect(f"root_{i}", eta)
        g.connect(eta, f"m_{i}")
        g.connect(eta, f"k_{i}")
        if md.damping:
            g.add(R(f"c_{i}", sym(f"c_{i}", md.damping)))
            g.connect(eta, f"c_{i}")
        b = sym(f"b_{i}", md.tip)
        if tip is not None:
            g.add(TF(f"tip_{i}", 1 / b))
            g.connect(tip, f"tip_{i}")
            g.connect(f"tip_{i}", eta)
    return ModalFragment(g, values, len(modes), rigid_inertia is not None, float(length))


def beam_fragment(beam: Union[ModalBeam, HubBeamModes], *, name: str = "beam", rigid: bool = True,
                  tip_port: bool = False, hub_port: bool | None = None,
                  damping_ratio: float | Sequence[float] = 0.0) -> ModalFragment:
    """Fragment of a :class:`ModalBeam` or of exact hub + beam modes.

    For :class:`HubBeamModes` the root gain is the hub rotation of the mode
    and the rigid mode carries the total inertia; for a pinned-free
    :class:`ModalBeam` the rigid mode is ``phi_0 = x`` with inertia
    ``rhoA L^3/3``; a clamped-free beam has no rigid mode and, by default,
    no hub port (its root is clamped to ground).

    Parameters
    ----------
    beam : ModalBeam or HubBeamModes
        The modes to turn into a fragment.
    name : str
        Graph name, prefix of the modal symbols.
    rigid : bool
        Include the rigid-body mode (pinned-free beams and hub modes only).
    tip_port : bool
        Expose ``Port('tip')``.
    hub_port : bool, optional
        Expose ``Port('hub')``; default: except for a clamped-free beam.
    damping_ratio : float or sequence of float
        Modal damping ratio (one value for all modes or one per mode).

    Returns
    -------
    ModalFragment

    Examples
    --------
    >>> from bondgraph.beam import hub_beam_modes
    >>> modes = hub_beam_modes(1.0, 1.0, 1.0, 2, hub_inertia=1.0)
    >>> frag = beam_fragment(modes, name="arm")
    >>> round(frag.values["arm.m_0"], 4)       # 1 + 1/3
    1.3333
    """
    n = len(beam.modes)
    zetas = [damping_ratio] * n if isinstance(damping_ratio, (int, float)) else list(damping_ratio)
    if len(zetas) != n:
        raise ValueError(f"damping_ratio: expected one value per mode ({n}), got {len(zetas)}")
    data = []
    if isinstance(beam, HubBeamModes):
        for hm, z in zip(beam.modes, zetas):
            k = hm.mass * hm.omega**2
            data.append(ModeData(hm.mass, k, 2 * z * hm.mass * hm.omega, hm.hub_angle, hm.tip_value))
        J0 = beam.total_inertia if rigid else None
        arm = beam.hub_radius + beam.L
    else:
        for md, z in zip(beam.modes, zetas):
            data.append(ModeData(md.mass, md.stiffness, 2 * z * md.mass * md.omega,
                                 md.root_slope, md.tip_value))
        has_rigid = beam.boundary == "pinned-free"
        J0 = beam.rigid_inertia if (rigid and has_rigid) else None
        arm = beam.L
        if hub_port is None:
            hub_port = beam.boundary != "clamped-free"
    return modal_fragment(data, name=name, rigid_inertia=J0, length=arm, tip_port=tip_port,
                          hub_port=True if hub_port is None else hub_port)
