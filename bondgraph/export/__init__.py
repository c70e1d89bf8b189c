"""Writing numeric plants to ``.mat``, ``.npz`` and JSON files, atomically.

Every writer first writes a temporary file in the target's directory and then
renames it over the target (:func:`os.replace`), so a failed export (bad path,
unwritable directory, a value that cannot be serialized) leaves neither a
partial file nor a temporary one behind, and an existing file is either kept
whole or replaced whole.  What sits at the path decides how it is written
(:mod:`bondgraph._support.write_target`): a regular file keeps its permission bits
(a ``0600`` file stays ``0600``); a symbolic link is kept and the file it
leads to is replaced; a character device or FIFO (``/dev/null``,
``/dev/stdout``, a named pipe) is written straight through, without a
temporary file; a directory, block device or socket is refused.  Readers
(:func:`load_json`, :func:`load_npz`) read only regular files under a size
cap (:mod:`bondgraph._support.safe_read`).

Formats
-------
``.mat`` (MATLAB 5, readable by MATLAB, Octave and :func:`scipy.io.loadmat`)
    Variables ``A``, ``B``, ``C``, ``D`` (double matrices); ``state_names``,
    ``input_names``, ``output_names`` and ``parameter_names`` (1-by-k cell
    arrays of char); ``parameter_values`` (1-by-k double, in the order of
    ``parameter_names``); ``model_name`` (char); ``format`` (char,
    ``"bondgraph-statespace"``) and ``format_version`` (double, 1).
    A plant taken about an operating point (a linearization, a model with
    constant sources: :attr:`NumericStateSpace.operating_point`) adds ``x0``,
    ``u0``, ``y0`` (column vectors of doubles in the order of the names: the
    matrices act on ``x - x0``, ``u - u0`` and give ``y - y0``) and
    ``operating_point`` (char: the point in words, with units when known);
    without them the plant is in the model's own variables.
    Parameter names such as ``motor.Ra`` are kept as strings, not as struct
    fields, since they are not MATLAB identifiers.  Names are written as
    MATLAB char arrays: ASCII names (quotes and newlines included) read back
    exactly in MATLAB and Octave; non-ASCII characters (accents, Greek) come
    back garbled in Octave 7, so keep names ASCII for ``.mat`` exchange.
    A sparse plant (:attr:`NumericStateSpace.is_sparse`) writes ``A``, ``B``,
    ``C``, ``D`` as MATLAB sparse matrices (``issparse`` is true in MATLAB;
    :func:`scipy.io.loadmat` gives ``scipy.sparse`` CSC matrices).

``.npz`` (:func:`numpy.savez`)
    The same arrays under the same names; names as unicode string arrays,
    ``model_name``, ``format`` and ``operating_point`` as 0-d string arrays,
    ``x0``, ``u0``, ``y0`` as 1-d arrays.  A sparse plant
    stores each of ``A``, ``B``, ``C``, ``D`` as four CSR arrays instead of
    one dense array (the layout of :func:`scipy.sparse.save_npz`, one set per
    matrix): ``A_data`` (float64 values), ``A_indices`` (column of each
    value), ``A_indptr`` (row pointers, rows + 1) and ``A_shape`` (2
    integers), and so on for ``B``, ``C``, ``D``; a reader tells the layouts
    apart by the presence of ``A`` or ``A_data``.  :func:`load_npz` reads
    both back (``scipy.sparse.csr_array((z["A_data"], z["A_indices"],
    z["A_indptr"]), shape=z["A_shape"])`` by hand).

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
          "parameters": {"J": 0.01, "K": 0.1}, // name -> value used
          "operating_point": {                 // optional: the point the plant is about
            "states": {"p_La": 0.0, "p_J": 0.0}, "inputs": {"V": 0.0},
            "outputs": {"omega": 0.0}, "how": "given"}
        }

    Matrices are row-major nested lists of finite numbers (JSON has no NaN or
    infinity: a plant with such entries cannot be written); a matrix with no
    rows is ``[]``.  :func:`load_json` reads the format back and checks every
    field (``model``, ``parameters``, ``operating_point`` and ``units`` -- signal
    name -> unit text, written by :mod:`bondgraph.library.units` -- may be left out; any other key
    missing, an unknown key, a repeated key or another version is refused).
    JSON stays dense (the format any reader can take as is): a sparse plant
    is written with its matrices expanded when it has at most
    :data:`~bondgraph.numeric.SPARSE_THRESHOLD` states, and refused above
    (``A`` alone would be ``n^2`` numbers, 400 MB of text at 5,000 states):
    write ``.mat`` or ``.npz``, which keep the matrices sparse.

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
from pathlib import Path
from typing import Any, Callable, Mapping, Optional, Sequence

import numpy as np

from ..errors import BondGraphError
from ..numeric.plant import NumericStateSpace
from ..numeric.sparse import SPARSE_THRESHOLD
from ..numeric.statespace import issparse

__all__ = ["ExportError", "FORMAT_NAME", "FORMAT_VERSION", "export", "export_mat", "export_npz",
           "export_json", "load_json", "load_npz", "atomic_write", "atomic_write_many", "FORMATS", "EXPORT_FORMATS",
           "decode_json", "number_problem", "checked_path", "HugeInt"]

FORMAT_NAME = "bondgraph-statespace"
FORMAT_VERSION = 1
#: file suffix -> format name understood by :func:`export` (numeric plants); and every format
#: ``bondgraph export`` writes (one table, in a module the command line reads without numpy)
from .._support.formats import EXPORT_FORMATS, FORMATS  # noqa: E402

from .._support.files import (ExportError, HugeInt, PathLike, short_repr, target_path, unlink_quietly, atomic_write,  # noqa: F401
                    atomic_write_many, checked_path, decode_json, number_problem)


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


def operating_vectors(plant: NumericStateSpace) -> Optional[tuple]:
    """``(x0, u0, y0, note)`` of a plant taken about an operating point, else None.

    Raises
    ------
    ExportError
        A point that is still symbolic or lacks a signal of the plant.
    """
    op = getattr(plant, "operating_point", None)
    if op is None:
        return None
    try:
        x0, u0, y0 = op.vectors(plant.state_names, plant.input_names, plant.output_names)
    except BondGraphError as exc:
        raise ExportError(f"plant {plant.name!r}: {exc}") from None
    for label, vec in (("x0", x0), ("u0", u0), ("y0", y0)):
        if not np.all(np.isfinite(vec)):
            raise ExportError(f"plant {plant.name!r}: its operating point {label} is not finite")
    return x0, u0, y0, op.note


def _mat_dict(plant: NumericStateSpace) -> dict[str, Any]:
    pnames = list(plant.parameters)
    point = operating_vectors(plant)
    extra = {} if point is None else {
        "x0": point[0].reshape(-1, 1), "u0": point[1].reshape(-1, 1),
        "y0": point[2].reshape(-1, 1), "operating_point": point[3]}
    return {**extra,
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
    if any((S.count_nonzero() if issparse(S) else np.count_nonzero(S)) for S in plant.state_shift):
        raise ExportError(
            f"plant {plant.name!r} uses shifted states z = x - S u (its derivation needs an "
            "input derivative): its A, B, C, D are not in the model's states "
            f"{', '.join(plant.state_names)}; export is refused rather than mislabelled")


def _refuse_non_finite(plant: NumericStateSpace, where: str, form: str) -> None:
    """:class:`ExportError` naming the first NaN, infinite or complex entry of A, B, C, D."""
    for key in ("A", "B", "C", "D"):
        matrix = getattr(plant, key)
        matrix = matrix.toarray() if issparse(matrix) else np.asarray(matrix)
        bad = np.argwhere(~np.isfinite(matrix)) if np.isrealobj(matrix) else np.argwhere(matrix.imag != 0)
        if bad.size:
            i, j = (int(k) for k in bad[0])
            raise ExportError(f"cannot write '{where}': {key}[{i}, {j}] is {matrix[i, j]} "
                              f"({form} holds finite real numbers only: no NaN, infinity or complex)",
                              path=where)


def export_mat(plant: NumericStateSpace, path: PathLike, *,
               units: Optional[Mapping[str, str]] = None) -> None:
    """Write a MATLAB/Octave ``.mat`` file (see the module docstring for its variables).

    Parameters
    ----------
    plant : NumericStateSpace
        The plant to write.
    path : str or path-like
        The file to write (replaced whole if it exists).
    units : mapping of str to str, optional
        Signal name -> unit text (:func:`bondgraph.library.units.model_units`); adds the
        cell arrays ``state_units``, ``input_units`` and ``output_units``
        (``''`` where a name has none).  Default: the plant's own
        :attr:`~bondgraph.numeric.NumericStateSpace.units`, when it has any.

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
    if units is None and plant.units:
        units = plant.units
    if units is not None:
        for key, names in (("state_units", plant.state_names), ("input_units", plant.input_names),
                           ("output_units", plant.output_names)):
            data[key] = _cell([str(units.get(n, "")) for n in names])
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
    data: dict[str, Any] = {}
    for key in "ABCD":
        M = getattr(p, key)
        if issparse(M):
            data.update({f"{key}_data": M.data, f"{key}_indices": M.indices,
                         f"{key}_indptr": M.indptr, f"{key}_shape": np.array(M.shape)})
        else:
            data[key] = M
    data.update({
        "state_names": np.array(p.state_names, dtype=str).reshape(-1),
        "input_names": np.array(p.input_names, dtype=str).reshape(-1),
        "output_names": np.array(p.output_names, dtype=str).reshape(-1),
        "parameter_names": np.array(pnames, dtype=str).reshape(-1),
        "parameter_values": np.array([p.parameters[n] for n in pnames], dtype=float),
        "model_name": np.array(p.name),
        "format": np.array(FORMAT_NAME),
        "format_version": np.array(FORMAT_VERSION),
    })
    if p.units:          # optional: signal name -> unit text, as the .mat and JSON files keep
        data["unit_names"] = np.array(list(p.units), dtype=str).reshape(-1)
        data["unit_texts"] = np.array([str(v) for v in p.units.values()], dtype=str).reshape(-1)
    point = operating_vectors(p)
    if point is not None:
        data.update({"x0": point[0], "u0": point[1], "y0": point[2],
                     "operating_point": np.array(point[3])})
    atomic_write(path, lambda fh: np.savez(fh, **data))


def load_npz(path: PathLike) -> NumericStateSpace:
    """Read a ``.npz`` file written by :func:`export_npz` (dense or sparse layout).

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    NumericStateSpace
        Sparse when the file holds the sparse layout.

    Raises
    ------
    ExportError
        Naming the file and the array at fault: not a regular file or too
        large (:data:`~bondgraph._support.safe_read.PLANT_LIMIT`), not a zip archive,
        missing arrays, wrong format name or version, a dtype that is not a
        real number (complex, text, objects) or not an integer for indices,
        NaN or infinity, repeated names, shapes that do not match the names,
        sparse indices out of range.  Only the format's members are read,
        each checked from its header before it is decompressed.

    Examples
    --------
    >>> import tempfile, os
    >>> from bondgraph.numeric import NumericStateSpace
    >>> ss = NumericStateSpace([[-1.0, 0.0], [1.0, -2.0]], [[1.0], [0.0]], [[0.0, 1.0]], [[0.0]],
    ...                        ("x1", "x2"), ("u",), ("y",), {"k": 2.0}, "two").to_sparse()
    >>> with tempfile.TemporaryDirectory() as d:
    ...     export_npz(ss, os.path.join(d, "two.npz"))
    ...     back = load_npz(os.path.join(d, "two.npz"))
    >>> back.is_sparse, back.A.toarray().tolist(), dict(back.parameters)
    (True, [[-1.0, 0.0], [1.0, -2.0]], {'k': 2.0})
    """
    from .npz_read import read_npz

    return read_npz(str(target_path(path)), FORMAT_NAME, FORMAT_VERSION)


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
    if p.is_sparse:
        if p.nstates > SPARSE_THRESHOLD:
            raise ExportError(
                f"plant {p.name!r} is sparse with {p.nstates} states: JSON holds dense matrices "
                f"(A alone would be {p.nstates ** 2} numbers); write .mat or .npz, which keep "
                "the matrices sparse")
        p = p.to_dense()
    return {
        "format": FORMAT_NAME,
        "version": FORMAT_VERSION,
        "model": p.name,
        "states": list(p.state_names),
        "inputs": list(p.input_names),
        "outputs": list(p.output_names),
        "A": p.A.tolist(), "B": p.B.tolist(), "C": p.C.tolist(), "D": p.D.tolist(),
        "parameters": dict(p.parameters),
        **_json_point(plant),
    }


def _json_point(plant: NumericStateSpace) -> dict[str, Any]:
    point = operating_vectors(plant)
    if point is None:
        return {}
    x0, u0, y0, _ = point
    return {"operating_point": {
        "states": dict(zip(plant.state_names, x0.tolist())),
        "inputs": dict(zip(plant.input_names, u0.tolist())),
        "outputs": dict(zip(plant.output_names, y0.tolist())),
        "how": plant.operating_point.how}}


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


def export_json(plant: NumericStateSpace, path: PathLike, *,
                units: Optional[Mapping[str, str]] = None) -> None:
    """Write the JSON format ``bondgraph-statespace`` version 1 (module docstring).

    Parameters
    ----------
    plant : NumericStateSpace
        The plant to write.
    path : str or path-like
        The file to write (replaced whole if it exists).
    units : mapping of str to str, optional
        Signal name -> unit text, written as the optional key ``"units"``
        (for the plant's states, inputs and outputs).  Default: the plant's
        own :attr:`~bondgraph.numeric.NumericStateSpace.units`, when it has any.

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
    if units is None and plant.units:
        units = plant.units
    if units is not None:
        doc["units"] = {n: str(units[n]) for n in (*doc["states"], *doc["inputs"], *doc["outputs"])
                        if n in units}
    where = os.fspath(target_path(path))
    _refuse_non_finite(plant, where, "JSON")
    for name, value in doc["parameters"].items():
        problem = number_problem(value)
        if problem is not None:
            raise ExportError(f"cannot write '{where}': parameter {name!r} {problem}", path=where)
    try:
        text = _json_text(doc)
    except (TypeError, ValueError) as exc:   # pragma: no cover - every field is checked above
        raise ExportError(f"cannot write '{where}': {exc}", path=where) from exc
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
        Naming the file, and the field at fault: the file cannot be read, is
        not UTF-8 JSON, repeats a key in one object, or does not follow the
        format.  Every field is checked: ``format`` and ``version`` (exactly
        1; other versions are refused), no unknown keys, ``model`` a string,
        the name lists lists of distinct strings, ``A``..``D`` nested lists of
        the shapes the name lists give, every number (matrix entries and
        parameter values) a finite real (not a bool, not ``NaN``).

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
    from .._support.safe_read import PLANT_LIMIT, read_regular

    target = target_path(path)
    raw = read_regular(str(target), "plant file", lambda message: ExportError(message, path=str(target)),
                       PLANT_LIMIT)
    doc = decode_json(raw, f"'{target}'", lambda message: ExportError(message, path=str(target)))
    return _plant_from_document(doc, str(target))


#: keys of the JSON document; ``model`` and ``parameters`` may be left out
_JSON_KEYS = ("format", "version", "model", "states", "inputs", "outputs", "A", "B", "C", "D",
              "parameters", "units", "operating_point")
_JSON_OPTIONAL = ("model", "parameters", "units", "operating_point")


def _plant_from_document(doc: Any, where: str) -> NumericStateSpace:
    """Check a parsed ``bondgraph-statespace`` document field by field and build the plant."""
    def fail(message: str) -> ExportError:
        return ExportError(f"'{where}': {message}", path=where)

    if not isinstance(doc, dict) or doc.get("format") != FORMAT_NAME:
        raise ExportError(f"'{where}' is not a {FORMAT_NAME} document "
                          f"(no \"format\": \"{FORMAT_NAME}\")", path=where)
    if "version" not in doc:
        raise fail('missing key "version"')
    version = doc["version"]
    if isinstance(version, bool) or not isinstance(version, int):
        raise fail(f'"version" must be an integer; got {type(version).__name__} {short_repr.repr(version)}')
    if version != FORMAT_VERSION:
        raise fail(f"unsupported {FORMAT_NAME} version {version}; this bondgraph reads version "
                   f"{FORMAT_VERSION} only")
    unknown = [k for k in doc if k not in _JSON_KEYS]
    if unknown:
        raise fail(f"unknown keys {', '.join(map(repr, unknown))}; a version {FORMAT_VERSION} "
                   f"document has {', '.join(_JSON_KEYS)}")
    missing = [k for k in _JSON_KEYS if k not in doc and k not in _JSON_OPTIONAL]
    if missing:
        raise fail(f"missing keys {', '.join(missing)}")
    model = doc.get("model", "")
    if not isinstance(model, str):
        raise fail(f'"model" must be a string; got {type(model).__name__} {short_repr.repr(model)}')
    names = {key: _json_names(doc[key], key, fail) for key in ("states", "inputs", "outputs")}
    n, m, p = (len(names[k]) for k in ("states", "inputs", "outputs"))
    sizes = {"A": (n, n, "states", "states"), "B": (n, m, "states", "inputs"),
             "C": (p, n, "outputs", "states"), "D": (p, m, "outputs", "inputs")}
    mats = {key: _json_matrix(doc[key], key, *sizes[key], fail) for key in "ABCD"}
    params_doc = doc.get("parameters", {})
    if not isinstance(params_doc, dict):
        raise fail(f'"parameters" must be an object of names to numbers; got '
                   f"{type(params_doc).__name__} {short_repr.repr(params_doc)}")
    units_doc = doc.get("units", {})
    if not isinstance(units_doc, dict) or not all(isinstance(v, str) for v in units_doc.values()):
        raise fail(f'"units" must be an object of names to unit texts; got {short_repr.repr(units_doc)}')
    for key, text in units_doc.items():       # shown on consoles: no control characters
        if not text.isprintable() or len(text) > 200:
            raise fail(f"the unit text of {short_repr.repr(key)} is not a printable unit name "
                       f"(control characters or over 200 characters): {text[:60]!r}")
    params = {}
    for key, value in params_doc.items():
        problem = number_problem(value)
        if problem is not None:
            raise fail(f"parameter {key!r} {problem}")
        params[key] = float(value)
    units = {k: v for k, v in units_doc.items()
             if k in {*names["states"], *names["inputs"], *names["outputs"]}}
    point = _json_read_point(doc.get("operating_point"), names, units, fail)
    try:
        return NumericStateSpace(mats["A"], mats["B"], mats["C"], mats["D"], names["states"],
                                 names["inputs"], names["outputs"], params, model,
                                 units=units, operating_point=point)
    except (BondGraphError, TypeError, ValueError) as exc:    # pragma: no cover - checked above
        raise fail(f"malformed {FORMAT_NAME} document: {exc}") from exc


def _json_read_point(doc: Any, names: Mapping, units: Mapping, fail: Callable[[str], ExportError]):
    """The :class:`~bondgraph.linear.OperatingPoint` of an ``"operating_point"`` object, or None."""
    if doc is None:
        return None
    from ..linear.point import OperatingPoint

    parts = {"states": "states", "inputs": "inputs", "outputs": "outputs"}
    if not isinstance(doc, dict) or set(doc) - {*parts, "how"} or not set(parts) <= set(doc):
        raise fail('"operating_point" must be an object with "states", "inputs", "outputs" '
                   f'(names to numbers) and optionally "how"; got {short_repr.repr(doc)}')
    values = {}
    for key, listed in parts.items():
        part = doc[key]
        if not isinstance(part, dict) or list(part) != list(names[listed]):
            raise fail(f'"operating_point"."{key}" must name exactly the {listed} '
                       f'{list(names[listed])}, in order; got {short_repr.repr(part)}')
        for n, v in part.items():
            problem = number_problem(v)
            if problem is not None:
                raise fail(f'"operating_point"."{key}" {n!r} {problem}')
        values[key] = {n: float(v) for n, v in part.items()}
    how = doc.get("how", "")
    if not isinstance(how, str):
        raise fail(f'"operating_point"."how" must be a string; got {short_repr.repr(how)}')
    return OperatingPoint(values["states"], values["inputs"], values["outputs"], units, how)


def _json_names(value: Any, key: str, fail: Callable[[str], ExportError]) -> tuple[str, ...]:
    if not isinstance(value, list):
        raise fail(f'"{key}" must be a list of names; got {type(value).__name__} {short_repr.repr(value)}')
    seen: set[str] = set()
    for k, name in enumerate(value):
        if not isinstance(name, str):
            raise fail(f'"{key}"[{k}] must be a string; got {type(name).__name__} {short_repr.repr(name)}')
        if name in seen:
            raise fail(f'"{key}" names {name!r} twice')
        seen.add(name)
    return tuple(value)


def _json_matrix(value: Any, key: str, rows: int, cols: int, row_names: str, col_names: str,
                 fail: Callable[[str], ExportError]) -> np.ndarray:
    shape = (f'"{key}" must be {rows} rows (one per name in "{row_names}") of {cols} numbers '
             f'(one per name in "{col_names}")')
    if not isinstance(value, list) or len(value) != rows:
        got = f"{len(value)} rows" if isinstance(value, list) else f"{type(value).__name__}"
        raise fail(f"{shape}; got {got}")
    out = np.zeros((rows, cols))
    for i, row in enumerate(value):
        if not isinstance(row, list) or len(row) != cols:
            got = f"{len(row)} numbers" if isinstance(row, list) else type(row).__name__
            raise fail(f"{shape}; row {i} has {got}")
        for j, entry in enumerate(row):
            problem = number_problem(entry)
            if problem is not None:
                raise fail(f"{key}[{i}][{j}] {problem}")
            out[i, j] = float(entry)
    return out


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
    bondgraph.ExportError: cannot tell the format of 'plant.txt': give format= one of mat, npz, json, or use a .mat, .npz or .json file name
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

