"""Reading a user's data file: what it is and how big it is, checked before a byte is read.

Every reader of a user's file (params, operating-point and study tables,
JSON and ``.npz`` plants) goes through :func:`read_regular` (or
:func:`open_regular`): the path must name a regular file (a FIFO would block
forever, ``/dev/zero`` would be read until memory runs out, a directory is
not data) of at most ``limit`` bytes, and the error raised names the file
and what it is for.  A file that changes under the reader (grows past the
limit, is swapped for a FIFO between the check and the ``open``) is refused
the same way: the file is opened without blocking and checked again on its
descriptor.

Examples
--------
>>> import tempfile, os
>>> with tempfile.TemporaryDirectory() as d:
...     os.mkfifo(os.path.join(d, "p.json"))
...     read_regular(os.path.join(d, "p.json"), "params file", ValueError)  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
ValueError: cannot read params file '.../p.json': it is a FIFO, not a regular file
"""

from __future__ import annotations

import os
import stat
from typing import IO, Callable

__all__ = ["TABLE_LIMIT", "PLANT_LIMIT", "read_regular", "open_regular", "kind_of"]

#: bytes a params, operating-point or study file may have (they are kilobytes in practice)
TABLE_LIMIT = 16 * 2**20
#: bytes a JSON or ``.npz`` plant file may have (and an ``.npz`` plant's arrays, decompressed)
PLANT_LIMIT = 1024 * 2**20

_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def kind_of(mode: int) -> str:
    """What a non-regular file is, in words (``'a FIFO'``, ``'a directory'``...).

    Examples
    --------
    >>> import stat
    >>> kind_of(stat.S_IFIFO | 0o644), kind_of(stat.S_IFCHR)
    ('a FIFO', 'a character device')
    """
    for test, words in _KINDS:
        if test(mode):
            return words
    return "not a regular file"


def open_regular(path: str, what: str, error: Callable[[str], Exception], limit: int) -> IO[bytes]:
    """Open ``path`` for binary reading once it is known to be a regular file of <= ``limit`` bytes.

    Parameters
    ----------
    path : str
        The path as the user gave it (symbolic links are followed: what
        counts is the file they lead to).
    what : str
        What the file is for, e.g. ``"params file"``; messages begin with it.
    error : callable
        ``error(message)`` returns the exception to raise.
    limit : int
        The largest size accepted, in bytes.

    Returns
    -------
    file object
        Open in binary mode, positioned at the start; the caller closes it.

    Raises
    ------
    Exception
        ``error(message)``: the file does not exist, cannot be opened, is not
        a regular file, or is larger than ``limit``.
    """
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0))
    except (FileNotFoundError, NotADirectoryError):
        raise error(f"{what} '{path}' does not exist") from None
    except IsADirectoryError:
        raise error(f"cannot read {what} '{path}': it is a directory, not a regular file") from None
    except OSError as exc:
        raise error(f"cannot read {what} '{path}': {exc.strerror or exc}") from None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise error(f"cannot read {what} '{path}': it is {kind_of(info.st_mode)}, not a "
                        "regular file")
        if info.st_size > limit:
            raise error(f"{what} '{path}' is {info.st_size:,} bytes, larger than the "
                        f"{limit:,} bytes a {what} may have")
        if hasattr(os, "set_blocking"):
            os.set_blocking(fd, True)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def read_regular(path: str, what: str, error: Callable[[str], Exception], limit: int = TABLE_LIMIT) -> bytes:
    """The bytes of ``path`` after :func:`open_regular`'s checks (at most ``limit`` bytes read).

    Examples
    --------
    >>> import tempfile, os
    >>> d = tempfile.mkdtemp()
    >>> with open(os.path.join(d, "p.json"), "w") as fh:
    ...     _ = fh.write('{"m": 2}')
    >>> read_regular(os.path.join(d, "p.json"), "params file", ValueError)
    b'{"m": 2}'
    >>> read_regular(os.path.join(d, "p.json"), "params file", ValueError, limit=4)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: params file '.../p.json' is 8 bytes, larger than the 4 bytes a params file may have
    >>> import shutil; shutil.rmtree(d)
    """
    with open_regular(path, what, error, limit) as fh:
        try:
            raw = fh.read(limit + 1)
        except OSError as exc:
            raise error(f"cannot read {what} '{path}': {exc.strerror or exc}") from None
    if len(raw) > limit:        # it grew after the check
        raise error(f"{what} '{path}' is larger than the {limit:,} bytes a {what} may have")
    return raw

