"""Switched model files on the command line: ``--mode`` and ``--average``, and the refusal.

A model file whose graph holds switches (:mod:`bondgraph.hybrid`) is a
switched model.  A command that needs one set of equations (``tf``, a
numeric plant or code from ``export``) takes one mode (``--mode on=S``) or
the state-space average (``--average d on=S on=D``); without either it
refuses and lists the modes -- never a silent answer for the mode the graph
was built in.  ``equations`` prints every mode, ``export -f fmu`` writes every
mode with event indicators, ``draw`` draws the initial mode (or ``--mode``),
and ``simulate`` runs with events.

A mode is written ``on=A,B`` (those switches on, every other off),
``off=C`` (C off, every other on), or both joined by ``;``
(``on=S;off=D``: then every switch must be named).

Examples
--------
>>> parse_mode("on=S, D")[0] == {"S", "D"}
True
>>> parse_mode("off=D")
(None, {'D'})
>>> parse_mode("on=")
(set(), None)
"""

from __future__ import annotations

from typing import Any, Optional

from ._common import CLIError, UsageError

__all__ = ["parse_mode", "switched_of", "chosen_model", "mode_text", "add_arguments"]


def add_arguments(p, *, average: bool = True) -> None:
    """``--mode`` (and ``--average``) of the commands that take a switched model."""
    p.add_argument("--mode", metavar="MODE",
                   help="switched model: the mode to use, on=A,B (those switches on, the others "
                        "off), off=C (C off, the others on) or on=A;off=C")
    if average:
        p.add_argument("--average", nargs=3, metavar=("DUTY", "ACTIVE", "PASSIVE"),
                       help="switched model: the state-space average with the new input DUTY, the "
                            "fraction of each period in mode ACTIVE (the rest in PASSIVE), e.g. "
                            "--average d on=S on=D")


def parse_mode(text: str, option: str = "--mode") -> tuple[Optional[set], Optional[set]]:
    """``(on, off)`` switch-name sets from ``on=A,B``, ``off=C`` or ``on=A;off=C`` (None: not given)."""
    on: Optional[set] = None
    off: Optional[set] = None
    parts = [part.strip() for part in text.split(";")]
    for part in parts:
        key, eq, names = part.partition("=")
        key = key.strip()
        if not eq or key not in ("on", "off"):
            raise UsageError(f"{option} {text!r}: expected on=NAMES, off=NAMES or on=NAMES;off=NAMES "
                             "(switch names separated by commas)")
        listed = {n.strip() for n in names.split(",") if n.strip()}
        if (on if key == "on" else off) is not None:
            raise UsageError(f"{option} {text!r}: {key}= is given twice")
        if key == "on":
            on = listed
        else:
            off = listed
    return on, off


def switched_of(defn) -> Any:
    """The :class:`~bondgraph.hybrid.SwitchedModel` of a model file's definition, or None."""
    return defn.switched


def mode_text(sm, mode) -> str:
    """A mode as the user writes it: ``on=S`` (or ``on=`` when every switch is off)."""
    return "on=" + ",".join(n for n in sm.switches if mode.is_on(n))


def modes_listing(sm) -> str:
    """``on=S (D off, S on); on=D (D on, S off); ...``: the consistent modes."""
    return "; ".join(f"{mode_text(sm, m)} ({m})" for m in sm.modes) or "none"


def to_mode(sm, text: str, option: str = "--mode"):
    """The :class:`~bondgraph.hybrid.Mode` a ``--mode`` text names (every switch set)."""
    on, off = parse_mode(text, option)
    switches = set(sm.switches)
    for names in (on, off):
        unknown = sorted((names or set()) - switches)
        if unknown:
            raise UsageError(f"{option} {text!r}: model {sm.name!r} has no switch "
                             f"{', '.join(map(repr, unknown))}; its switches are {', '.join(sm.switches)}")
    if on is not None and off is not None:
        both = sorted(on & off)
        if both:
            raise UsageError(f"{option} {text!r}: switch {', '.join(both)} is given both on and off")
        rest = sorted(switches - on - off)
        if rest:
            raise UsageError(f"{option} {text!r}: give every switch's state when naming both on= "
                             f"and off= (missing {', '.join(rest)})")
    elif on is not None:
        off = switches - on
    else:
        on = switches - (off or set())
        off = off or set()
    from ..hybrid import Mode

    return Mode(on=frozenset(on), off=frozenset(off))


def _derived(sm, mode, option: str, text: str):
    from ..hybrid import ModeError

    try:
        return sm.derived(mode).user
    except ModeError:
        raise CLIError(f"{option} {text!r}: mode ({mode}) of model {sm.name!r} is not consistent "
                       f"(its switch states contradict each other); the consistent modes are "
                       f"{modes_listing(sm)}") from None


def chosen_model(args, defn, command: str):
    """The one model a command works on: the definition's, or a switched model's mode or average.

    Raises
    ------
    CLIError
        A switched model without ``--mode`` or ``--average`` (the modes listed).
    UsageError
        ``--mode`` or ``--average`` for a model without switches, or both given.
    """
    mode_arg = getattr(args, "mode", None)
    average = getattr(args, "average", None)
    sm = switched_of(defn)
    if sm is None:
        if mode_arg is not None or average is not None:
            raise UsageError(f"--mode and --average apply to switched models; model {defn.name!r} "
                             "has no switch")
        return defn.derive()
    if mode_arg is not None and average is not None:
        raise UsageError("give --mode or --average, not both")
    if mode_arg is not None:
        return _derived(sm, to_mode(sm, mode_arg), "--mode", mode_arg)
    if average is not None:
        duty, active, passive = average
        if not duty.isidentifier():
            raise UsageError(f"--average: the duty-cycle input must be a name; got {duty!r}")
        modes = [to_mode(sm, text, "--average") for text in (active, passive)]
        for mode, text in zip(modes, (active, passive)):
            _derived(sm, mode, "--average", text)
        from ..hybrid import ModeError

        try:
            return sm.average(duty, modes[0], modes[1])
        except ModeError as exc:
            raise CLIError(f"--average: {exc}") from None
    pair = _example_pair(sm)
    raise CLIError(
        f"model {sm.name!r} is switched (switches {', '.join(sm.switches)}): '{command}' needs one "
        f"mode or the state-space average; choose a mode with --mode (consistent modes: "
        f"{modes_listing(sm)})" + (f" or average two modes with --average DUTY ACTIVE PASSIVE "
                                    f"(e.g. --average d {pair})" if pair else ""))


def _example_pair(sm) -> str:
    """Two consistent modes with the same states (an averaging pair), as ``on=.. on=..``."""
    modes = sm.modes
    for k, a in enumerate(modes):
        for b in modes[k + 1:]:
            if sm.derived(a).user.states == sm.derived(b).user.states:
                if b == sm.initial:
                    a, b = b, a
                return f"{mode_text(sm, a)} {mode_text(sm, b)}"
    return ""
