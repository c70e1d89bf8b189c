"""Signal names for python-control, shared by the numeric and transfer-function layers."""

from __future__ import annotations

from typing import Sequence

__all__ = ["control_labels"]


def control_labels(names: Sequence[str]) -> list[str]:
    """Signal names acceptable to python-control, which forbids ``'.'``.

    Dots of hierarchical names become underscores; a clash with another name
    gets a numeric suffix.

    Examples
    --------
    >>> control_labels(["motor.V", "F", "motor_V"])
    ['motor_V_2', 'F', 'motor_V']
    """
    out: list[str] = []
    taken = {n for n in names if "." not in n}
    for name in names:
        label = name.replace(".", "_")
        if "." in name and label in taken:
            k = 2
            while f"{label}_{k}" in taken:
                k += 1
            label = f"{label}_{k}"
        elif label in out:
            k = 2
            while f"{label}_{k}" in taken or f"{label}_{k}" in out:
                k += 1
            label = f"{label}_{k}"
        taken.add(label)
        out.append(label)
    return out


_STATE_PREFIXES = ("p", "q", "x", "h")


def latex_name(name: str) -> str:
    r"""LaTeX of a (possibly hierarchical) signal, state or parameter name.

    Sub-model paths are set upright before the local name, so ``link.a_1``
    reads :math:`\mathrm{link}.a_{1}` and the state ``p_link.m_1`` reads
    :math:`p_{\mathrm{link}.m_{1}}`; plain names print as sympy prints them.

    Examples
    --------
    >>> latex_name("omega"), latex_name("link.a_1"), latex_name("p_link.m_1")
    ('\\omega', '\\mathrm{link}.a_{1}', 'p_{\\mathrm{link}.m_{1}}')
    """
    import sympy

    if "." not in name:
        return sympy.latex(sympy.Symbol(name))
    head, sep, rest = name.partition("_")
    if sep and head in _STATE_PREFIXES and "." in rest:
        return f"{head}_{{{_path_latex(rest)}}}"
    return _path_latex(name)


def latex_dot(name: str) -> str:
    r"""LaTeX of the time derivative of a state (or signal) name.

    The name prints as :func:`latex_name` does, with the dot over the base
    symbol only and subscripts and superscripts outside: ``x_2`` reads
    :math:`\dot{x}_{2}`, not :math:`\dot{x_{2}}`.  This is how sympy prints a
    symbol with the ``dot`` modifier (``Symbol("xdot_2")``) and the time
    derivative of ``x_2(t)`` (``sympy.physics.vector.vlatex``), and how the
    seed papers write them (``\dot{\eta}_1(t)``, Soares et al., Eq. 22).  A sub-model path stays upright and
    undotted: the state ``p_link.m_1`` reads :math:`\dot{p}_{\mathrm{link}.m_{1}}`,
    the signal ``link.a_1`` reads :math:`\mathrm{link}.\dot{a}_{1}`.

    Parameters
    ----------
    name : str
        State or signal name, e.g. ``"p_J"``, ``"x2"`` or ``"p_link.m_1"``.

    Returns
    -------
    str
        LaTeX without math delimiters.

    Examples
    --------
    >>> latex_dot("p_J"), latex_dot("x2"), latex_dot("theta_1"), latex_dot("omega")
    ('\\dot{p}_{J}', '\\dot{x}_{2}', '\\dot{\\theta}_{1}', '\\dot{\\omega}')
    >>> latex_dot("p_link.m_1"), latex_dot("link.a_1")
    ('\\dot{p}_{\\mathrm{link}.m_{1}}', '\\mathrm{link}.\\dot{a}_{1}')
    """
    import sympy
    from sympy.printing.conventions import split_super_sub

    if "." in name:
        head, sep, rest = name.partition("_")
        if sep and head in _STATE_PREFIXES and "." in rest:
            return f"{latex_dot(head)}_{{{_path_latex(rest)}}}"
        *prefix, local = name.split(".")
        return ".".join([rf"\mathrm{{{p}}}" for p in prefix] + [latex_dot(local)])
    base, sups, subs = split_super_sub(name)
    if not base:
        return rf"\dot{{{latex_name(name)}}}"
    dotted = base + "dot" + "".join("_" + x for x in subs) + "".join("__" + x for x in sups)
    return sympy.latex(sympy.Symbol(dotted))


def _path_latex(path: str) -> str:
    import sympy

    *prefix, local = path.split(".")
    return ".".join([rf"\mathrm{{{p}}}" for p in prefix] + [sympy.latex(sympy.Symbol(local))])


def tex(expr) -> str:
    r"""``sympy.latex`` with hierarchical symbol names set by :func:`latex_name`.

    Examples
    --------
    >>> import sympy
    >>> tex(sympy.Symbol("motor.Ra") * sympy.Symbol("i"))
    'i \\mathrm{motor}.Ra'
    """
    import sympy

    names = {s: latex_name(s.name) for s in getattr(expr, "free_symbols", ())
             if isinstance(s, sympy.Symbol) and "." in s.name}
    return sympy.latex(expr, symbol_names=names) if names else sympy.latex(expr)
