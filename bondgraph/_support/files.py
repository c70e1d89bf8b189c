"""Files written all or nothing, and JSON read strictly: the I/O under every exporter.

:func:`atomic_write` and :func:`atomic_write_many` write into temporary
files beside the targets and rename them only when every writer succeeded,
rolling back on a failed rename, so a failed export leaves neither a partial
file nor a temporary one.  :func:`decode_json` reads JSON refusing repeated
keys and keeping integers too large for a float (:class:`HugeInt`) so a
checker can name the field; :func:`number_problem` says why a value is not a
finite real number.  Used by :mod:`bondgraph.export`, the command line, code
generation and drawing.
"""

from __future__ import annotations

import json
import math
import numbers
import os
import reprlib
import secrets
import shutil
import tempfile
from pathlib import Path
from typing import IO, Any, Callable, Mapping, Optional, Sequence, Union

from ..errors import BondGraphError

__all__ = ["ParamsFileError", "load_params", "flatten_numbers", "ExportError", "HugeInt", "PathLike", "atomic_write", "atomic_write_many",
           "checked_path", "decode_json", "number_problem"]

PathLike = Union[str, "os.PathLike[str]"]


class ExportError(BondGraphError, OSError):
    """A file could not be written (or read back); the message names the path.

    Attributes
    ----------
    filename : str or None
        The path at fault.
    errno : int or None
        The operating system's error number, when there was one.
    """

    __module__ = "bondgraph"      # tracebacks name it where users import it: bondgraph.ExportError

    def __init__(self, message: str, *, path: Optional[str] = None, errno: Optional[int] = None) -> None:
        super().__init__(message)
        self.filename = path
        self.errno = errno

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


class HugeInt:
    """An integer literal of a JSON text too large for a float (kept as its digits).

    :func:`decode_json` gives one in place of such an integer, so a checker
    can name the field instead of meeting an ``OverflowError``.
    """

    __slots__ = ("text",)

    def __init__(self, text: str) -> None:
        self.text = text

    def __repr__(self) -> str:
        return f"<integer of {len(self.text.lstrip('-'))} digits>"


class _DuplicateKey(Exception):
    def __init__(self, key: str) -> None:
        super().__init__(key)
        self.key = key



#: deepest nesting of arrays and tables a parameter file may have (a parser's recursion
#: would otherwise decide, and the interpreter's recursion limit is not ours to rely on)
MAX_NESTING = 1000


def _readable_text(raw: bytes, quotes: str, fail, what: str) -> str:
    """``raw`` as UTF-8 text nested at most :data:`MAX_NESTING` deep, or ``fail(message)``."""
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise fail(f"{what} is not UTF-8 text: {exc}") from None
    if _nesting(text, quotes) > MAX_NESTING:
        raise fail(f"{what} is nested too deeply to be read")
    return text


def _nesting(text: str, quotes: str) -> int:
    """The deepest nesting of ``[``/``{`` in ``text`` outside quoted strings."""
    depth = deepest = 0
    quote = ""
    escaped = False
    for ch in text:
        if quote:
            if escaped:
                escaped = False
            elif ch == "\\" and quote == '"':
                escaped = True
            elif ch == quote:
                quote = ""
        elif ch in quotes:
            quote = ch
        elif ch in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif ch in "]}":
            depth -= 1
    return deepest

def _unique_pairs(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise _DuplicateKey(key)
        out[key] = value
    return out


def _parse_int(text: str) -> Any:
    # float() first: it takes any number of digits (int() refuses more than 4300)
    return HugeInt(text) if math.isinf(float(text)) else int(text)


def decode_json(raw: bytes, what: str, fail: Callable[[str], Exception]) -> Any:
    """Parse JSON bytes strictly: UTF-8, no duplicate keys, bounded nesting.

    Parameters
    ----------
    raw : bytes
        The file's content.
    what : str
        How messages name the file, e.g. ``"params file 'p.json'"``.
    fail : callable
        ``fail(message)`` returns the exception to raise.

    Returns
    -------
    object
        As :func:`json.loads`, except that an integer too large for a float
        is a :class:`HugeInt` (``NaN`` and ``Infinity`` are read as floats,
        for the caller's check to name the field).

    Examples
    --------
    >>> decode_json(b'{"a": 1, "a": 2}', "'x.json'", ValueError)
    Traceback (most recent call last):
    ...
    ValueError: 'x.json': the key 'a' appears twice in one object
    """
    text = _readable_text(raw, '"', fail, what)
    try:
        return json.loads(text, object_pairs_hook=_unique_pairs, parse_int=_parse_int)
    except _DuplicateKey as exc:
        raise fail(f"{what}: the key {exc.key!r} appears twice in one object") from None
    except RecursionError:
        raise fail(f"{what} is nested too deeply to be read") from None
    except ValueError as exc:
        raise fail(f"{what} is not valid JSON: {exc}") from None


short_repr = reprlib.Repr()
short_repr.maxstring = short_repr.maxother = 40


def number_problem(value: Any) -> Optional[str]:
    """Why ``value`` is not a finite real number (int or float, not bool); None if it is.

    The text completes a sentence whose subject is the field: ``f"{name} {problem}"``.

    Examples
    --------
    >>> number_problem(2), number_problem(True), number_problem(10 ** 400)
    (None, 'must be a number; got bool True', 'is an integer too large for a float (above 1.8e308)')
    """
    if isinstance(value, HugeInt):
        return f"is an integer too large for a float ({len(value.text.lstrip('-'))} digits)"
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        return f"must be a number; got {type(value).__name__} {short_repr.repr(value)}"
    try:
        number = float(value)
    except OverflowError:
        what = "an integer" if isinstance(value, numbers.Integral) else "a number"
        return f"is {what} too large for a float (above 1.8e308)"
    if not math.isfinite(number):
        return f"must be finite; got {short_repr.repr(value)}"
    return None


def atomic_write_many(items: Sequence[tuple[PathLike, Callable[[Any], None]]], *,
                      binary: bool = True) -> None:
    """Write several files all or nothing.

    Each ``writer(fileobj)`` writes one file's content into a temporary file
    in the target's directory.  Only once every writer has succeeded are the
    temporary files renamed over their targets, one by one.  When one of
    those renames fails (or the process is interrupted between them), the
    targets already renamed are rolled back: a file that existed before gets
    its previous content again (it was kept as a hard link, or a copy, beside
    it), a new file is removed.  Temporary and backup files are removed on
    every path, so the directory ends as it was, or with every file new.

    Parameters
    ----------
    items : sequence of (path, writer)
        Each target path with the callable that writes its content.  The
        paths must be distinct.
    binary : bool, default True
        Open the temporary files in binary (``"wb"``) or text mode.

    Raises
    ------
    ExportError
        Naming the path that could not be written.  When a rollback itself
        fails (a disk removed mid-way) the message names the files left new.

    Notes
    -----
    What sits at a target decides how it is written
    (:mod:`bondgraph._support.write_target`): a regular file is replaced keeping
    its mode; a symbolic link is kept and the file it leads to replaced; a
    character device or FIFO is written straight through (no temporary
    file, the node stays); a directory, block device or socket is refused.
    Several files take an exclusive lock on their folders while written.

    Examples
    --------
    >>> import tempfile, os
    >>> with tempfile.TemporaryDirectory() as d:
    ...     atomic_write_many([(os.path.join(d, "a.txt"), lambda f: f.write("A")),
    ...                        (os.path.join(d, "b.txt"), lambda f: f.write("B"))], binary=False)
    ...     sorted(os.listdir(d))
    ['a.txt', 'b.txt']
    """
    from .write_target import inspect_target, locked_folders

    kinds = [inspect_target(target_path(path), ExportError) for path, _ in items]
    seen: set[str] = set()
    for kind in kinds:
        key = os.path.normcase(os.path.abspath(kind.path))
        if key in seen:
            raise ExportError(f"cannot write '{kind.given}' twice in one operation", path=str(kind.given))
        seen.add(key)
    if len(items) > 1:
        with locked_folders([kind.path for kind in kinds]):
            _write_many(kinds, [writer for _, writer in items], binary)
    else:
        _write_many(kinds, [writer for _, writer in items], binary)


def _write_many(kinds: Sequence[Any], writers: Sequence[Callable[[Any], None]], binary: bool) -> None:
    """:func:`atomic_write_many` once the targets are classified (and locked)."""
    from .write_target import render, write_through

    temps: list[tuple[str, Path]] = []
    through: list[tuple[Any, bytes]] = []           # devices and FIFOs: written last, straight
    backups: list[str] = []                         # every backup made, removed at the end
    renamed: list[tuple[Path, Optional[str]]] = []  # (target, its backup or None if it was new)
    try:
        for kind, writer in zip(kinds, writers):
            if kind.through:
                try:
                    through.append((kind, render(writer, binary)))
                except ExportError:
                    raise
                except Exception as exc:
                    raise ExportError(f"cannot write '{kind.given}': {type(exc).__name__}: {exc}",
                                      path=str(kind.given), errno=getattr(exc, "errno", None)) from exc
            else:
                temps.append((_write_temp(kind.path, writer, binary, kind.old), kind.path))
        for tmp, target in temps:
            # one file: the rename alone is atomic; several: keep each old file to roll back to
            backup = _backup(target) if len(temps) > 1 else None
            if backup is not None:
                backups.append(backup)
            try:
                os.replace(tmp, target)
            except OSError as exc:
                raise ExportError(f"cannot write '{target}': {exc.strerror or exc}",
                                  path=str(target), errno=exc.errno) from exc
            renamed.append((target, backup))
        for kind, data in through:
            write_through(kind, data, ExportError)
    except BaseException as exc:
        left = _roll_back(renamed)
        if left and isinstance(exc, ExportError):
            raise ExportError(f"{exc}; rolling back also failed, these files are new: "
                              f"{', '.join(left)}", path=exc.filename, errno=exc.errno) from exc
        raise
    finally:
        for tmp, _ in temps:
            unlink_quietly(tmp)
        for backup in backups:
            unlink_quietly(backup)


def _backup(target: Path) -> Optional[str]:
    """A hard link (or else a copy) of ``target`` beside it; None when there is no file."""
    if not os.path.lexists(target):
        return None
    folder = target.parent if str(target.parent) else Path(".")
    for _ in range(100):
        name = str(folder / f".{target.name}.{os.getpid()}.{secrets.token_hex(4)}.bak")
        try:
            os.link(target, name, follow_symlinks=False)
            return name
        except FileExistsError:
            continue
        except OSError:
            break           # no hard links here: copy instead
    name = ""
    try:
        fd, name = tempfile.mkstemp(dir=folder, prefix=f".{target.name}.", suffix=".bak")
        os.close(fd)
        shutil.copy2(target, name, follow_symlinks=False)
        return name
    except OSError as exc:
        if name:
            unlink_quietly(name)
        raise ExportError(f"cannot write '{target}': cannot keep its previous content to roll "
                          f"back to: {exc.strerror or exc}", path=str(target), errno=exc.errno) from exc


def _roll_back(renamed: Sequence[tuple[Path, Optional[str]]]) -> list[str]:
    """Put back what the renamed targets held; returns the targets that could not be."""
    left = []
    for target, backup in reversed(renamed):
        try:
            if backup is None:
                os.unlink(target)
            else:
                os.replace(backup, target)
        except OSError:
            left.append(str(target))
    return left


def atomic_write(path: PathLike, writer: Callable[[Any], None], *, binary: bool = True) -> None:
    """Write one file atomically: ``writer(fileobj)`` into a temp file, then rename.

    Parameters
    ----------
    path : str or path-like
        The target file.
    writer : callable
        ``writer(fileobj)`` writes the content into the open temporary file.
    binary : bool, default True
        Open the temporary file in binary (``"wb"``) or text mode.

    Raises
    ------
    ExportError
        Naming ``path``; no partial or temporary file is left.

    Examples
    --------
    >>> atomic_write("/no/such/dir/x.txt", lambda f: f.write("x"), binary=False)
    Traceback (most recent call last):
    ...
    bondgraph.ExportError: cannot write '/no/such/dir/x.txt': the directory '/no/such/dir' does not exist
    """
    atomic_write_many([(path, writer)], binary=binary)


def checked_path(path: Any, what: str, error: Callable[[str], Exception]) -> str:
    """``os.fspath(path)``, a str without NUL characters; else ``error(message)`` naming ``what``.

    Parameters
    ----------
    path : str or path-like
        A path as the user gave it.
    what : str
        What the path is for, e.g. ``"model file"``; it begins the message.
    error : callable
        ``error(message)`` returns the exception to raise.

    Returns
    -------
    str
        The path, spelled as given.

    Examples
    --------
    >>> checked_path("a\\0b.json", "params file", ValueError)
    Traceback (most recent call last):
    ...
    ValueError: params file 'a\\x00b.json' cannot be used: its name holds a NUL character
    """
    try:
        text = os.fspath(path)
    except TypeError:
        raise error(f"{what} path must be a str or path; got {type(path).__name__}") from None
    if not isinstance(text, str):
        raise error(f"{what} path must be a str or path; got {type(text).__name__} {text!r}")
    if "\0" in text:
        raise error(f"{what} {text!r} cannot be used: its name holds a NUL character")
    return text


def target_path(path: PathLike) -> Path:
    return Path(checked_path(path, "output", ExportError))


def _write_temp(target: Path, writer: Callable[[Any], None], binary: bool,
                old: Optional[os.stat_result] = None) -> str:
    folder = target.parent if str(target.parent) else Path(".")
    try:
        if target.is_dir():
            raise ExportError(f"cannot write '{target}': it is a directory", path=str(target), errno=21)
        if not folder.exists():
            raise ExportError(f"cannot write '{target}': the directory '{folder}' does not exist",
                              path=str(target), errno=2)
        if not folder.is_dir():
            raise ExportError(f"cannot write '{target}': '{folder}' is not a directory",
                              path=str(target), errno=20)
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{target.name}.", suffix=".tmp")
    except OSError as exc:
        if isinstance(exc, ExportError):
            raise
        raise ExportError(f"cannot write '{target}': {exc.strerror or exc}",
                          path=str(target), errno=exc.errno) from exc
    try:
        fh: IO[Any] = os.fdopen(fd, "wb") if binary else os.fdopen(fd, "w", encoding="utf-8")
        with fh:
            writer(fh)
            fh.flush()
            os.fsync(fh.fileno())
        from .write_target import copy_owner_and_mode

        copy_owner_and_mode(tmp, old, 0o666 & ~_umask())      # a 0600 file stays 0600
    except ExportError:
        unlink_quietly(tmp)
        raise
    except Exception as exc:
        unlink_quietly(tmp)
        errno = getattr(exc, "errno", None)
        raise ExportError(f"cannot write '{target}': {type(exc).__name__}: {exc}",
                          path=str(target), errno=errno) from exc
    except BaseException:       # KeyboardInterrupt, SystemExit: no temporary file is left
        unlink_quietly(tmp)
        raise
    return tmp


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def unlink_quietly(path: str) -> None:
    try:
        os.unlink(path)
    except FileNotFoundError:
        pass
    except OSError:  # pragma: no cover - nothing more can be done
        pass


def read_table(path: Any, what: str, error: Callable[[str], Exception]) -> tuple[str, Any]:
    """Read a ``.json`` or ``.toml`` file strictly: ``(path as given, decoded data)``.

    JSON goes through :func:`decode_json` (repeated keys refused, huge
    integers kept as :class:`HugeInt`), TOML through :mod:`tomllib`.  Every
    failure is ``error(message)`` naming ``what`` and the path; the caller
    checks the data's shape.  Used by params files and study files.

    Examples
    --------
    >>> read_table("/no/such/params.json", "params file", ValueError)
    Traceback (most recent call last):
    ...
    ValueError: params file '/no/such/params.json' does not exist
    """
    name = checked_path(path, what, error)
    suffix = Path(name).suffix.lower()
    if suffix not in (".json", ".toml"):
        raise error(f"{what} '{name}' must be .json or .toml")
    from .safe_read import TABLE_LIMIT, read_regular

    raw = read_regular(name, what, error, TABLE_LIMIT)     # a regular file, kilobytes: no FIFO, no /dev/zero
    label = f"{what} '{name}'"
    if suffix == ".json":
        return name, decode_json(raw, label, error)
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        try:
            import tomli as tomllib  # type: ignore[no-redef]
        except ModuleNotFoundError:
            raise error(f"{label}: TOML needs Python 3.11+ or the 'tomli' package; "
                        "use a .json file instead") from None
    text = _readable_text(raw, "\"'", error, label)
    try:
        return name, tomllib.loads(text)
    except RecursionError:
        raise error(f"{label} is nested too deeply to be read") from None
    except ValueError as exc:  # tomllib.TOMLDecodeError, also for a repeated key
        raise error(f"{label} is not valid TOML: {exc}") from None


# --------------------------------------------------------------------------- parameter files
class ParamsFileError(BondGraphError, ValueError):
    """A parameter file is missing, unreadable, or not a mapping of names to numbers."""

    #: the command line's exit status for this error
    exit_status = 1


def load_params(path: "str | os.PathLike[str]") -> dict[str, float]:
    """Read a JSON or TOML parameter file into ``{name: value}``.

    Nested mappings give dotted names (``{"motor": {"Ra": 1}}`` is
    ``motor.Ra``).  Every value must be a finite real number (not a bool, not
    a string).

    Parameters
    ----------
    path : str or path-like
        A ``.json`` or ``.toml`` file.

    Returns
    -------
    dict of str to float

    Raises
    ------
    ParamsFileError
        Naming the file and, for a bad value, the parameter.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d, "p.toml")
    ...     _ = p.write_text('J = 0.01\\n[motor]\\nRa = 1.5\\n')
    ...     load_params(p)
    {'J': 0.01, 'motor.Ra': 1.5}
    """
    name, data = read_table(path, "params file", ParamsFileError)
    what = f"params file '{name}'"
    if not isinstance(data, dict):
        raise ParamsFileError(
            f"{what} must hold a mapping of parameter names to numbers; "
            f"got a {type(data).__name__}")
    return flatten_numbers(data, name)


def flatten_numbers(data: Mapping, path: str) -> dict[str, float]:
    """Nested mappings to dotted names, depth first in file order (no recursion: any depth)."""
    out: dict[str, float] = {}
    stack = [("", iter(data.items()))]
    while stack:
        prefix, items = stack[-1]
        for key, value in items:
            name = f"{prefix}{key}"
            if isinstance(value, dict):
                stack.append((name + ".", iter(value.items())))
                break
            problem = number_problem(value)
            if problem is not None:
                raise ParamsFileError(f"params file '{path}': parameter {name!r} {problem}")
            if name in out:
                raise ParamsFileError(f"params file '{path}': parameter {name!r} is given twice")
            out[name] = float(value)
        else:
            stack.pop()
    return out
