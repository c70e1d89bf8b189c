"""Writing numeric plants to ``.mat``, ``.npz`` and JSON files, atomically.

Every writer first writes a temporary file in the target's directory and then
renames it over the target (:func:`os.replace`), so a failed export (bad path,
unwritable directory, a value that cannot be serialized) leaves neither a
partial file nor a temporary one behind, and an existing file is either kept
whole or replaced whole.

Formats
-------
``.mat`` (MATLAB 5, readable by MATLAB, Octave and :func:`scipy.io.loadmat`)
    Variables ``A``, ``B``, ``C``, ``D`` (double matrices); ``state_names``,
    ``input_names``, ``output_names`` and ``parameter_names`` (1-by-k cell
    arrays of char); ``parameter_values`` (1-by-k double, in the order of
    ``parameter_names``); ``model_name`` (char); ``format`` (char,
    ``"bondgraph-statespace"``) and ``format_version`` (double, 1).
    Parameter names such as ``motor.Ra`` are kept as strings, not as struct
    fields, since they are not MATLAB identifiers.

``.npz`` (:func:`numpy.savez`)
    The same arrays under the same names; names as unicode string arrays,
    ``model_name`` and ``format`` as 0-d string arrays.

JSON, format ``bondgraph-statespace`` version 1
    One object::

        {
          "format": "bondgraph-statespace",   // always this string
          "version": 1,                        // integer; bumped on incompatible change
          "model": "dc_motor",                 // model name (may be "")
          "states":  ["p_La", "p_J"],          // names, in the order of the rows of A
          "inputs":  ["V"],                    // names, in the order of the columns of B
          "outputs": ["omega"],                // names, in the order of the rows of C
          "A": [[-2.0, -10.0], [0.2, -10.0]],  // n rows of n numbers
          "B": [[1.0], [0.0]],                 // n rows of m numbers
          "C": [[0.0, 100.0]],                 // p rows of n numbers
          "D": [[0.0]],                        // p rows of m numbers
          "parameters": {"J": 0.01, "K": 0.1}  // name -> value used
        }

    Matrices are row-major nested lists of finite numbers (JSON has no NaN or
    infinity: a plant with such entries cannot be written).  :func:`load_json`
    reads the format back and checks it.

Examples
--------
>>> import tempfile, os, numpy as np, scipy.io
>>> from bondgraph.numeric import NumericStateSpace
>>> ss = NumericStateSpace([[-1.0]], [[1.0]], [[2.0]], [[0.0]], ("x",), ("u",), ("y",),
...                        {"tau": 1.0}, "lag")
>>> with tempfile.TemporaryDirectory() as d:
...     export_mat(ss, os.path.join(d, "lag.mat"))
...     m = scipy.io.loadmat(os.path.join(d, "lag.mat"))
...     export_json(ss, os.path.join(d, "lag.json"))
...     back = load_json(os.path.join(d, "lag.json"))
>>> m["A"], str(m["state_names"][0, 0][0]), back.parameters["tau"]
(array([[-1.]]), 'x', 1.0)
"""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path
from typing import IO, Any, Callable, Optional, Sequence, Union

import numpy as np

from .errors import BondGraphError
from .numeric.plant import NumericStateSpace

__all__ = ["ExportError", "FORMAT_NAME", "FORMAT_VERSION", "export", "export_mat", "export_npz",
           "export_json", "load_json", "atomic_write", "atomic_write_many", "FORMATS"]

FORMAT_NAME = "bondgraph-statespace"
FORMAT_VERSION = 1
#: file suffix -> format name understood by :func:`export`
FORMATS = {".mat": "mat", ".npz": "npz", ".json": "json"}

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

    def __init__(self, message: str, *, path: Optional[str] = None, errno: Optional[int] = None) -> None:
        super().__init__(message)
        self.filename = path
        self.errno = errno

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


def atomic_write_many(items: Sequence[tuple[PathLike, Callable[[Any], None]]], *,
                      binary: bool = True) -> None:
    """Write several files all-or-nothing (as far as renames allow).

    Each ``writer(fileobj)`` writes one file's content into a temporary file
    in the target's directory.  Only once all writers have succeeded are the
    temporary files renamed over their targets.  On any failure every
    temporary file is removed and :class:`ExportError` names the path.

    Parameters
    ----------
    items : sequence of (path, writer)
        Each target path with the callable that writes its content.
    binary : bool, default True
        Open the temporary files in binary (``"wb"``) or text mode.

    Examples
    --------
    >>> import tempfile, os
    >>> with tempfile.TemporaryDirectory() as d:
    ...     atomic_write_many([(os.path.join(d, "a.txt"), lambda f: f.write("A")),
    ...                        (os.path.join(d, "b.txt"), lambda f: f.write("B"))], binary=False)
    ...     sorted(os.listdir(d))
    ['a.txt', 'b.txt']
    """
    temps: list[tuple[str, Path]] = []
    try:
        for path, writer in items:
            target = _target(path)
            tmp = _write_temp(target, writer, binary)
            temps.append((tmp, target))
        for tmp, target in temps:
            try:
                os.replace(tmp, target)
            except OSError as exc:
                raise ExportError(f"cannot write '{target}': {exc.strerror or exc}",
                                  path=str(target), errno=exc.errno) from exc
    finally:
        for tmp, _ in temps:
            if os.path.exists(tmp):
                try:
                    os.unlink(tmp)
                except OSError:  # pragma: no cover - nothing more can be done
                    pass


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
    bondgraph.export.ExportError: cannot write '/no/such/dir/x.txt': the directory '/no/such/dir' does not exist
    """
    atomic_write_many([(path, writer)], binary=binary)


def _target(path: PathLike) -> Path:
    try:
        return Path(os.fspath(path))
    except TypeError:
        raise ExportError(f"output path must be a str or path; got {type(path).__name__}") from None


def _write_temp(target: Path, writer: Callable[[Any], None], binary: bool) -> str:
    folder = target.parent if str(target.parent) else Path(".")
    if target.is_dir():
        raise ExportError(f"cannot write '{target}': it is a directory", path=str(target), errno=21)
    if not folder.exists():
        raise ExportError(f"cannot write '{target}': the directory '{folder}' does not exist",
                          path=str(target), errno=2)
    if not folder.is_dir():
        raise ExportError(f"cannot write '{target}': '{folder}' is not a directory",
                          path=str(target), errno=20)
    try:
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{target.name}.", suffix=".tmp")
    except OSError as exc:
        raise ExportError(f"cannot write '{target}': {exc.strerror or exc}",
                          path=str(target), errno=exc.errno) from exc
    try:
        fh: IO[Any] = os.fdopen(fd, "wb") if binary else os.fdopen(fd, "w", encoding="utf-8")
        with fh:
            writer(fh)
            fh.flush()
            os.fsync(fh.fileno())
        mode = 0o666 & ~_umask()
        os.chmod(tmp, mode)
    except ExportError:
        _unlink(tmp)
        raise
    except Exception as exc:
        _unlink(tmp)
        errno = getattr(exc, "errno", None)
        raise ExportError(f"cannot write '{target}': {type(exc).__name__}: {exc}",
                          path=str(target), errno=errno) from exc
    return tmp


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _unlink(path: str) -> None:
    try:
        os.unlink(path)
    except OSError:  # pragma: no cover
        pass


def _check_plant(plant: Any) -> NumericStateSpace:
    if not isinstance(plant, NumericStateSpace):
        raise ExportError("expected a NumericStateSpace (from bondgraph.numeric); "
                          f"got {type(plant).__name__}")
    return plant


def _cell(names: Sequence[str]) -> np.ndarray:
    out = np.empty((1, len(names)), dtype=object)
    for i, n in enumerate(names):
        out[0, i] = str(n)
    return out


def _mat_dict(plant: NumericStateSpace) -> dict[str, Any]:
    pnames = list(plant.parameters)
    return {
        "A": plant.A, "B": plant.B, "C": plant.C, "D": plant.D,
        "state_names": _cell(plant.state_names),
        "input_names": _cell(plant.input_names),
        "output_names": _cell(plant.output_names),
        "parameter_names": _cell(pnames),
        "parameter_values": np.array([[plant.parameters[n] for n in pnames]], dtype=float).reshape(1, -1),
        "model_name": plant.name,
        "format": FORMAT_NAME,
        "format_version": float(FORMAT_VERSION),
    }


def _check_exportable(plant: NumericStateSpace) -> None:
    """A, B, C, D must be the whole plant: refuse improper or state-shifted plants."""
    if not isinstance(plant, NumericStateSpace):
        return          # the writer's own check names the wrong type
    if not plant.is_proper:
        raise ExportError(
            f"plant {plant.name!r} is improper (an output depends on an input derivative, "
            "D_derivatives is nonzero): A, B, C, D cannot hold it; export the proper outputs "
            "only, or write the transfer functions (model.transfer_function(...))")
    if any(np.any(S != 0.0) for S in plant.state_shift):
        raise ExportError(
            f"plant {plant.name!r} uses shifted states z = x - S u (its derivation needs an "
            "input derivative): its A, B, C, D are not in the model's states "
            f"{', '.join(plant.state_names)}; export is refused rather than mislabelled")


def export_mat(plant: NumericStateSpace, path: PathLike) -> None:
    """Write a MATLAB/Octave ``.mat`` file (see the module docstring for its variables).

    Parameters
    ----------
    plant : NumericStateSpace
        The plant to write.
    path : str or path-like
        The file to write (replaced whole if it exists).

    Raises
    ------
    ExportError
        Naming ``path``; nothing is left behind.

    Examples
    --------
    >>> import tempfile, os
    >>> from bondgraph.numeric import NumericStateSpace
    >>> ss = NumericStateSpace([[-1.0]], [[1.0]], [[2.0]], [[0.0]], ("x",), ("u",), ("y",),
    ...                        {"tau": 1.0}, "lag")
    >>> import scipy.io
    >>> with tempfile.TemporaryDirectory() as d:
    ...     export_mat(ss, os.path.join(d, "lag.mat"))
    ...     m = scipy.io.loadmat(os.path.join(d, "lag.mat"))
    >>> m["C"], str(m["model_name"][0])
    (array([[2.]]), 'lag')
    """
    _check_exportable(plant)
    import scipy.io

    data = _mat_dict(_check_plant(plant))
    atomic_write(path, lambda fh: scipy.io.savemat(fh, data, format="5", long_field_names=False,
                                                   do_compression=False, oned_as="row"))


def export_npz(plant: NumericStateSpace, path: PathLike) -> None:
    """Write a numpy ``.npz`` archive (same arrays as the ``.mat`` file).

    The file is written to exactly ``path`` (no ``.npz`` is appended).

    Parameters
    ----------
    plant : NumericStateSpace
        The plant to write.
    path : str or path-like
        The file to write (replaced whole if it exists).

    Raises
    ------
    ExportError
        Naming ``path``; nothing is left behind.

    Examples
    --------
    >>> import tempfile, os
    >>> from bondgraph.numeric import NumericStateSpace
    >>> ss = NumericStateSpace([[-1.0]], [[1.0]], [[2.0]], [[0.0]], ("x",), ("u",), ("y",),
    ...                        {"tau": 1.0}, "lag")
    >>> import numpy as np
    >>> with tempfile.TemporaryDirectory() as d:
    ...     export_npz(ss, os.path.join(d, "lag.npz"))
    ...     with np.load(os.path.join(d, "lag.npz")) as z:
    ...         z["A"], z["state_names"], z["parameter_values"]
    (array([[-1.]]), array(['x'], dtype='<U1'), array([1.]))
    """
    _check_exportable(plant)
    p = _check_plant(plant)
    pnames = list(p.parameters)
    # values typed Any: numpy's stub would match ``**data`` to ``allow_pickle: bool`` too
    data: dict[str, Any] = {
        "A": p.A, "B": p.B, "C": p.C, "D": p.D,
        "state_names": np.array(p.state_names, dtype=str).reshape(-1),
        "input_names": np.array(p.input_names, dtype=str).reshape(-1),
        "output_names": np.array(p.output_names, dtype=str).reshape(-1),
        "parameter_names": np.array(pnames, dtype=str).reshape(-1),
        "parameter_values": np.array([p.parameters[n] for n in pnames], dtype=float),
        "model_name": np.array(p.name),
        "format": np.array(FORMAT_NAME),
        "format_version": np.array(FORMAT_VERSION),
    }
    atomic_write(path, lambda fh: np.savez(fh, **data))


def to_json_dict(plant: NumericStateSpace) -> dict[str, Any]:
    """The JSON document (a plain dict) for ``plant``; see the module docstring.

    Examples
    --------
    >>> from bondgraph.numeric import NumericStateSpace
    >>> ss = NumericStateSpace([[-1.0]], [[1.0]], [[2.0]], [[0.0]], ("x",), ("u",), ("y",), {"k": 2.0}, "lag")
    >>> to_json_dict(ss)["A"], to_json_dict(ss)["format"]
    ([[-1.0]], 'bondgraph-statespace')
    """
    p = _check_plant(plant)
    return {
        "format": FORMAT_NAME,
        "version": FORMAT_VERSION,
        "model": p.name,
        "states": list(p.state_names),
        "inputs": list(p.input_names),
        "outputs": list(p.output_names),
        "A": p.A.tolist(), "B": p.B.tolist(), "C": p.C.tolist(), "D": p.D.tolist(),
        "parameters": dict(p.parameters),
    }


def _json_text(doc: dict[str, Any]) -> str:
    """One key per line, one matrix row per line."""
    parts = []
    for key, value in doc.items():
        if key in ("A", "B", "C", "D") and value:
            body = ",\n    ".join(json.dumps(row, allow_nan=False) for row in value)
            text = f"[\n    {body}\n  ]"
        else:
            text = json.dumps(value, allow_nan=False)
        parts.append(f"  {json.dumps(key)}: {text}")
    return "{\n" + ",\n".join(parts) + "\n}\n"


def export_json(plant: NumericStateSpace, path: PathLike) -> None:
    """Write the JSON format ``bondgraph-statespace`` version 1 (module docstring).

    Parameters
    ----------
    plant : NumericStateSpace
        The plant to write.
    path : str or path-like
        The file to write (replaced whole if it exists).

    Raises
    ------
    ExportError
        Naming ``path`` -- also when a matrix entry is NaN or infinite, which
        JSON cannot represent; nothing is left behind.

    Examples
    --------
    >>> import tempfile, os
    >>> from bondgraph.numeric import NumericStateSpace
    >>> ss = NumericStateSpace([[-1.0]], [[1.0]], [[2.0]], [[0.0]], ("x",), ("u",), ("y",),
    ...                        {"tau": 1.0}, "lag")
    >>> import json
    >>> with tempfile.TemporaryDirectory() as d:
    ...     export_json(ss, os.path.join(d, "lag.json"))
    ...     with open(os.path.join(d, "lag.json")) as fh:
    ...         doc = json.load(fh)
    >>> doc["format"], doc["model"], doc["A"], doc["parameters"]
    ('bondgraph-statespace', 'lag', [[-1.0]], {'tau': 1.0})
    """
    _check_exportable(plant)
    doc = to_json_dict(plant)
    try:
        text = _json_text(doc)
    except ValueError as exc:
        raise ExportError(f"cannot write '{os.fspath(path)}': {exc} (JSON has no NaN or infinity)") from exc
    atomic_write(path, lambda fh: fh.write(text), binary=False)


def load_json(path: PathLike) -> NumericStateSpace:
    """Read a ``bondgraph-statespace`` JSON file back into a :class:`NumericStateSpace`.

    Parameters
    ----------
    path : str or path-like
        A file written by :func:`export_json` (or following its format).

    Returns
    -------
    NumericStateSpace

    Raises
    ------
    ExportError
        If the file cannot be read, is not JSON, or does not follow the format.

    Examples
    --------
    >>> import tempfile, os
    >>> from bondgraph.numeric import NumericStateSpace
    >>> ss = NumericStateSpace([[-1.0]], [[1.0]], [[2.0]], [[0.0]], ("x",), ("u",), ("y",),
    ...                        {"tau": 1.0}, "lag")
    >>> with tempfile.TemporaryDirectory() as d:
    ...     export_json(ss, os.path.join(d, "lag.json"))
    ...     back = load_json(os.path.join(d, "lag.json"))
    >>> back.name, back.state_names, back.B, dict(back.parameters)
    ('lag', ('x',), array([[1.]]), {'tau': 1.0})
    """
    target = _target(path)
    try:
        doc = json.loads(target.read_text(encoding="utf-8"))
    except OSError as exc:
        raise ExportError(f"cannot read '{target}': {exc.strerror or exc}",
                          path=str(target), errno=exc.errno) from exc
    except ValueError as exc:
        raise ExportError(f"'{target}' is not valid JSON: {exc}") from exc
    if not isinstance(doc, dict) or doc.get("format") != FORMAT_NAME:
        raise ExportError(f"'{target}' is not a {FORMAT_NAME} document (no \"format\": \"{FORMAT_NAME}\")")
    if doc.get("version") != FORMAT_VERSION:
        raise ExportError(f"'{target}': unsupported {FORMAT_NAME} version {doc.get('version')!r}; "
                          f"expected {FORMAT_VERSION}")
    missing = [k for k in ("states", "inputs", "outputs", "A", "B", "C", "D") if k not in doc]
    if missing:
        raise ExportError(f"'{target}': missing keys {', '.join(missing)}")
    n, m, p = len(doc["states"]), len(doc["inputs"]), len(doc["outputs"])
    try:
        mats = [np.array(doc[k], dtype=float).reshape(shape) for k, shape in
                (("A", (n, n)), ("B", (n, m)), ("C", (p, n)), ("D", (p, m)))]
        params = {str(k): float(v) for k, v in dict(doc.get("parameters", {})).items()}
        A, B, C, D = mats
        return NumericStateSpace(A, B, C, D, tuple(doc["states"]), tuple(doc["inputs"]),
                                 tuple(doc["outputs"]), params, str(doc.get("model", "")))
    except (TypeError, ValueError) as exc:
        raise ExportError(f"'{target}': malformed {FORMAT_NAME} document: {exc}") from exc


def export(plant: NumericStateSpace, path: PathLike, *, format: Optional[str] = None) -> None:
    """Write ``plant`` in the format given or implied by the suffix (.mat, .npz, .json).

    Parameters
    ----------
    plant : NumericStateSpace
        The plant to write.
    path : str or path-like
        The file to write (replaced whole if it exists).
    format : {'mat', 'npz', 'json'}, optional
        Default: from the suffix of ``path``.

    Raises
    ------
    ExportError
        Unknown format, or the file could not be written.

    Examples
    --------
    >>> from bondgraph.numeric import NumericStateSpace
    >>> ss = NumericStateSpace([[-1.0]], [[1.0]], [[1.0]], [[0.0]], ("x",), ("u",), ("y",))
    >>> export(ss, "plant.txt")
    Traceback (most recent call last):
    ...
    bondgraph.export.ExportError: cannot tell the format of 'plant.txt': give format= one of mat, npz, json, or use a .mat, .npz or .json file name
    """
    fmt = format
    if fmt is None:
        fmt = FORMATS.get(Path(os.fspath(path)).suffix.lower())
        if fmt is None:
            raise ExportError(f"cannot tell the format of '{os.fspath(path)}': give format= one of "
                              "mat, npz, json, or use a .mat, .npz or .json file name")
    writers = {"mat": export_mat, "npz": export_npz, "json": export_json}
    if fmt not in writers:
        raise ExportError(f"unknown export format {fmt!r}; expected one of {', '.join(writers)}")
    writers[fmt](plant, path)

