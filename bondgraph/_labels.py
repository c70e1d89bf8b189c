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
    r"""LaTeX of the time derivative of a state name.

    Examples
    --------
    >>> latex_dot("p_J"), latex_dot("p_link.m_1"), latex_dot("theta")
    ('\\dot{p}_{J}', '\\dot{p}_{\\mathrm{link}.m_{1}}', '\\dot{\\theta}')
    """
    head, sep, rest = name.partition("_")
    if sep and head in _STATE_PREFIXES and rest:
        inner = _path_latex(rest) if "." in rest else latex_name(rest)
        return rf"\dot{{{head}}}_{{{inner}}}"
    return rf"\dot{{{latex_name(name)}}}"


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
