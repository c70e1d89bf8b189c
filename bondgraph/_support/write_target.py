"""What sits at an output path, and how :func:`bondgraph.files.atomic_write_many` treats it.

The policy (issue 23; audit C08, C28-C30, K01):

* **nothing there, or a regular file**: written to a temporary file beside it
  and renamed over it; an existing file's permission bits (and owner, where
  the process may set it) are copied onto the new file, so a ``0600`` file
  stays ``0600``.  A hard link to the old file keeps the old content (the
  rename gives the path a new file).
* **a symbolic link**: kept.  The file it leads to is the one replaced
  (resolved with :func:`os.path.realpath`; a dangling link's target is
  created), so ``out.json -> results/out.json`` still points at the new
  content.
* **a character device or a FIFO** (``/dev/null``, ``/dev/stdout`` on a
  terminal or a pipe, a named pipe): written straight through, without a
  temporary file and without replacing the node: the content is produced in
  memory first (a writer that fails writes nothing), then written with one
  ``open``.  Opening a FIFO waits for its reader, as any program writing to it.
* **a directory, a block device, a socket**: refused (:class:`ExportError`).

Several files written together (a ``.c`` file and its header) take an
exclusive :func:`fcntl.flock` on their folders for the whole operation, so two
processes writing the same pair cannot leave one's ``.c`` beside the other's
``.h``.
"""

from __future__ import annotations

import contextlib
import io
import os
import stat
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterator, Optional, Sequence

from .safe_read import kind_of
from ..errors import BondGraphError

__all__ = ["Target", "inspect_target", "write_through", "locked_folders", "copy_owner_and_mode"]


@dataclass(frozen=True)
class Target:
    """An output path as written: ``path`` (the rename's target), ``through``, the old file's stat."""

    given: Path
    path: Path
    through: bool
    old: Optional[os.stat_result]


def inspect_target(target: Path, error: Callable[..., BondGraphError]) -> Target:
    """Classify ``target`` (see the module docstring); ``error(message, path=..., errno=...)`` on refusal.

    Examples
    --------
    >>> import tempfile, os
    >>> from pathlib import Path
    >>> from bondgraph._support.files import ExportError
    >>> with tempfile.TemporaryDirectory() as d:
    ...     os.mkfifo(os.path.join(d, "pipe"))
    ...     os.symlink("real.json", os.path.join(d, "link.json"))
    ...     fifo = inspect_target(Path(d, "pipe"), ExportError)
    ...     link = inspect_target(Path(d, "link.json"), ExportError)
    >>> fifo.through, link.through, link.path.name
    (True, False, 'real.json')
    """
    try:
        info = os.stat(target)          # follows links, /proc/self/fd/N included
    except (FileNotFoundError, NotADirectoryError):
        info = None                     # the writer names the missing folder
    except OSError as exc:
        raise error(f"cannot write '{target}': {exc.strerror or exc}", path=str(target),
                    errno=exc.errno) from None
    if info is not None and (stat.S_ISCHR(info.st_mode) or stat.S_ISFIFO(info.st_mode)):
        return Target(target, target, True, info)
    if info is not None and not stat.S_ISREG(info.st_mode) and not stat.S_ISDIR(info.st_mode):
        raise error(f"cannot write '{target}': it is {kind_of(info.st_mode)}, not a regular file; "
                    "give a file name", path=str(target), errno=None)
    path = Path(os.path.realpath(target)) if os.path.islink(target) else target
    return Target(target, path, False, info if info is not None and stat.S_ISREG(info.st_mode) else None)


def copy_owner_and_mode(tmp: str, old: Optional[os.stat_result], default_mode: int) -> None:
    """Give the temporary file the old file's permission bits and owner (else ``default_mode``)."""
    if old is None:
        os.chmod(tmp, default_mode)
        return
    if hasattr(os, "chown") and (old.st_uid, old.st_gid) != (os.getuid(), os.getgid()):
        with contextlib.suppress(OSError):      # only root (or the owner, for the group) may
            os.chown(tmp, old.st_uid, old.st_gid)
    os.chmod(tmp, stat.S_IMODE(old.st_mode))


def render(writer: Callable[[Any], None], binary: bool) -> bytes:
    """The bytes ``writer`` produces, in memory."""
    buffer: Any = io.BytesIO() if binary else io.StringIO()
    writer(buffer)
    data = buffer.getvalue()
    return data if binary else data.encode("utf-8")


def write_through(target: Target, data: bytes, error: Callable[..., BondGraphError]) -> None:
    """Write ``data`` into the character device or FIFO ``target`` (no temporary file)."""
    try:
        fd = os.open(target.given, os.O_WRONLY | getattr(os, "O_BINARY", 0))
        try:
            view = memoryview(data)
            while view:
                view = view[os.write(fd, view):]
        finally:
            os.close(fd)
    except OSError as exc:
        raise error(f"cannot write '{target.given}': {exc.strerror or exc}", path=str(target.given),
                    errno=exc.errno) from None


@contextlib.contextmanager
def locked_folders(paths: Sequence[Path]) -> Iterator[None]:
    """Hold an exclusive ``flock`` on each folder of ``paths`` (in a fixed order: no deadlock)."""
    try:
        import fcntl
    except ImportError:         # pragma: no cover - Windows: no advisory locks here
        yield
        return
    folders = sorted({os.path.realpath(p.parent if str(p.parent) else ".") for p in paths})
    fds = []
    try:
        for folder in folders:
            try:
                fd = os.open(folder, os.O_RDONLY)
            except OSError:
                continue                        # the writer's own check names the folder
            fds.append(fd)
            fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        for fd in fds:
            os.close(fd)                        # closing releases the lock
