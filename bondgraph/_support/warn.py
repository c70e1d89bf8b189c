"""Warnings attributed to the user's line, however deep in the package they are raised.

Examples
--------
>>> import warnings
>>> from bondgraph._support.warn import warn_user
>>> with warnings.catch_warnings(record=True) as caught:
...     warnings.simplefilter("always")
...     warn_user("careful", UserWarning)
>>> caught[0].filename.startswith("<doctest")   # the line that called warn_user
True
"""

from __future__ import annotations

import os
import sys
import warnings
from types import FrameType
from typing import Optional

__all__ = ["warn_user", "user_stacklevel"]

_PACKAGE = os.path.dirname(os.path.dirname(os.path.abspath(__file__))) + os.sep


def user_stacklevel() -> int:
    """``stacklevel``, for a ``warnings.warn`` called by the caller of this function, of the
    first frame outside the package and importlib."""
    frame: Optional[FrameType] = sys._getframe(1)
    level = 1
    while frame is not None:
        name = frame.f_code.co_filename
        if "importlib" in name and "_bootstrap" in name:
            frame = frame.f_back               # warnings skips these frames itself
            continue
        if not name.startswith(_PACKAGE):
            return level
        frame, level = frame.f_back, level + 1
    return level


def warn_user(message: str, category: type[Warning]) -> None:
    """``warnings.warn`` pointing at the user's line."""
    warnings.warn(message, category, stacklevel=user_stacklevel())
