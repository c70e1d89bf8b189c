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
