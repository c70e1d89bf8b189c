"""Reading a ``bondgraph-statespace`` ``.npz`` archive without trusting it.

:func:`read_npz` is the body of :func:`bondgraph.export.load_npz`.  The file
must be a regular file under :data:`~bondgraph._support.safe_read.PLANT_LIMIT`
bytes; only the members the format has are read (others are never
decompressed); each member's ``.npy`` header (dtype, shape, hence size) and
its size in the zip directory are checked before its data is decompressed;
numbers must be finite reals (no complex, no NaN, no text), names distinct
strings, and a sparse matrix's index arrays are checked in full
(``check_format(full_check=True)``: in range, ``indptr`` monotone) before
the matrix is used, since scipy does not check them and an index out of
range corrupts memory.  Every failure is an :class:`~bondgraph.files.ExportError`
naming the file and the member.
"""

from __future__ import annotations

import zipfile
from typing import Any, Callable

import numpy as np

from .._support.safe_read import PLANT_LIMIT, open_regular
from ..errors import BondGraphError
from .._support.files import ExportError

__all__ = ["ARRAYS_LIMIT", "read_npz"]

_NAMES = ("state_names", "input_names", "output_names", "parameter_names")
_UNITS = ("unit_names", "unit_texts")       # optional: the signals' units
_SPARSE_PARTS = ("data", "indices", "indptr", "shape")
_NUMERIC = "fiu"
#: bytes the format's arrays of one file may hold once decompressed (checked from the zip directory)
ARRAYS_LIMIT = PLANT_LIMIT


def _member_spec(key: str) -> tuple[str, Any]:
    if key in "ABCD":
        return _NUMERIC, 2
    if key in _NAMES or key in _UNITS:
        return "U", 1
    if key in ("model_name", "format", "operating_point"):
        return "U", 0
    if key in ("x0", "u0", "y0"):
        return _NUMERIC, 1
    if key == "format_version":
        return "iu", 0
    if key == "parameter_values":
        return _NUMERIC, 1
    part = key.split("_", 1)[1]
    return {"data": (_NUMERIC, 1), "indices": ("iu", 1), "indptr": ("iu", 1), "shape": ("iu", 1)}[part]


#: the operating point's arrays (optional, all or none)
_POINT = ("x0", "u0", "y0", "operating_point")


def read_npz(path: str, FORMAT_NAME: str, FORMAT_VERSION: int) -> Any:
    """Read and check ``path`` (format name and version given by :mod:`bondgraph.export`).

    Returns the :class:`~bondgraph.numeric.NumericStateSpace`.
    """
    from ..numeric.plant import NumericStateSpace

    def fail(message: str) -> ExportError:
        return ExportError(f"'{path}': {message}", path=path)

    with open_regular(path, "plant file", lambda m: ExportError(m, path=path), PLANT_LIMIT) as fh:
        try:
            archive = zipfile.ZipFile(fh)
        except (zipfile.BadZipFile, EOFError, OSError, ValueError) as exc:
            raise fail(f"not a numpy .npz archive (a zip file of .npy arrays): {exc}") from None
        with archive:
            arrays = _read_members(archive, fail)
    if str(arrays.get("format", "")) != FORMAT_NAME:
        raise fail(f'not a {FORMAT_NAME} archive (no "format" array holding "{FORMAT_NAME}")')
    version = arrays.get("format_version")
    if version is None or int(version) != FORMAT_VERSION:
        raise fail(f"unsupported format_version {version}; this bondgraph reads {FORMAT_VERSION} "
                   "(a 0-d integer array)")
    missing = [k for k in (*_NAMES, "parameter_values", "model_name") if k not in arrays]
    sparse = {k for k in "ABCD" if k not in arrays and all(f"{k}_{p}" in arrays for p in _SPARSE_PARTS)}
    missing += [f"{k} (or {k}_data, {k}_indices, {k}_indptr, {k}_shape)" for k in "ABCD"
                if k not in arrays and k not in sparse]
    if missing:
        raise fail(f"missing arrays {', '.join(missing)}")
    if sparse and len(sparse) != 4:
        raise fail("A, B, C, D must all be dense or all sparse")
    names = {k: tuple(str(v) for v in arrays[k]) for k in _NAMES}
    for key, seq in names.items():
        twice = sorted({s for s in seq if seq.count(s) > 1})
        if twice:
            raise fail(f"{key} names {', '.join(map(repr, twice))} more than once")
    n, m, p = (len(names[k]) for k in ("state_names", "input_names", "output_names"))
    shapes = {"A": (n, n), "B": (n, m), "C": (p, n), "D": (p, m)}
    mats = {key: (_sparse(arrays, key, shapes[key], fail) if sparse else _dense(arrays, key, shapes[key], fail))
            for key in "ABCD"}
    values = arrays["parameter_values"]
    if values.shape[0] != len(names["parameter_names"]):
        raise fail(f"{len(names['parameter_names'])} parameter_names but {values.shape[0]} parameter_values")
    _finite(values, "parameter_values", fail)
    units = _units(arrays, {*names["state_names"], *names["input_names"], *names["output_names"]},
                   fail)
    point = _point(arrays, names, fail)
    try:
        return NumericStateSpace(mats["A"], mats["B"], mats["C"], mats["D"], names["state_names"],
                                 names["input_names"], names["output_names"],
                                 dict(zip(names["parameter_names"], values.astype(float).tolist())),
                                 str(arrays["model_name"]), units=units,
                                 operating_point=point)
    except (BondGraphError, TypeError, ValueError) as exc:
        raise fail(f"malformed {FORMAT_NAME} archive: {exc}") from exc


def _units(arrays: dict, signals: set, fail: Callable[[str], ExportError]) -> dict[str, str]:
    """The optional units (signal name -> printable unit text) of an archive."""
    if not any(k in arrays for k in _UNITS):
        return {}
    if not all(k in arrays for k in _UNITS):
        raise fail("unit_names and unit_texts must be given together")
    keys = [str(v) for v in arrays["unit_names"]]
    texts = [str(v) for v in arrays["unit_texts"]]
    if len(keys) != len(texts):
        raise fail(f"{len(keys)} unit_names but {len(texts)} unit_texts")
    for key, text in zip(keys, texts):
        if not text.isprintable() or len(text) > 200:
            raise fail(f"the unit text of {key[:40]!r} is not a printable unit name (control "
                       f"characters or over 200 characters): {text[:60]!r}")
    return {k: v for k, v in zip(keys, texts) if k in signals}


def _point(arrays: dict, names: dict, fail: Callable[[str], ExportError]):
    """The operating point stored as ``x0``, ``u0``, ``y0`` (all or none), or None."""
    keys = [k for k in _POINT if k in arrays]
    if not keys:
        return None
    if len(keys) != len(_POINT):
        raise fail(f"an operating point needs {', '.join(_POINT)}; got only {', '.join(keys)}")
    from ..linear.point import OperatingPoint

    parts = []
    for key, listed in (("x0", "state_names"), ("u0", "input_names"), ("y0", "output_names")):
        vec = arrays[key]
        if vec.ndim != 1 or vec.shape[0] != len(names[listed]) or vec.dtype.kind not in "fiu":
            raise fail(f"{key} must be a 1-d array of {len(names[listed])} numbers (one per "
                       f"name in {listed}); got shape {vec.shape}, dtype {vec.dtype}")
        _finite(vec, key, fail)
        parts.append(dict(zip(names[listed], vec.astype(float).tolist())))
    return OperatingPoint(parts[0], parts[1], parts[2], how=str(arrays["operating_point"]))


def _expected(key: str) -> bool:
    if key in "ABCD" or key in _NAMES or key in _POINT or key in _UNITS or key in (
            "parameter_values", "model_name", "format", "format_version"):
        return bool(key)
    head, _, part = key.partition("_")
    return head in ("A", "B", "C", "D") and part in _SPARSE_PARTS


def _read_members(archive: zipfile.ZipFile, fail: Callable[[str], ExportError]) -> dict[str, np.ndarray]:
    arrays: dict[str, np.ndarray] = {}
    budget = ARRAYS_LIMIT
    for info in archive.infolist():
        if not info.filename.endswith(".npy"):
            continue
        key = info.filename[:-4]
        if not _expected(key):
            continue            # never decompressed
        if key in arrays:
            raise fail(f"the member {key} appears twice in the archive")
        if info.file_size > budget:
            raise fail(f"the member {key} holds {info.file_size:,} bytes decompressed, more than the "
                       f"{ARRAYS_LIMIT:,} bytes a plant file's arrays may have in total")
        budget -= info.file_size
        kinds, ndim = _member_spec(key)
        try:
            with archive.open(info) as member:
                version = np.lib.format.read_magic(member)
                shape, _fortran, dtype = (np.lib.format.read_array_header_1_0(member) if version == (1, 0)
                                          else np.lib.format.read_array_header_2_0(member))
                if dtype.kind not in kinds or dtype.hasobject:
                    raise fail(f"the array {key} has dtype {dtype}; expected "
                               f"{_kind_words(kinds)}")
                if ndim is not None and len(shape) != ndim:
                    raise fail(f"the array {key} has shape {shape}; expected {ndim} dimension(s)")
                if int(np.prod(shape, dtype=object)) * dtype.itemsize > info.file_size:
                    raise fail(f"the array {key} claims shape {shape} but its member is too small")
            with archive.open(info) as member:
                arrays[key] = np.lib.format.read_array(member, allow_pickle=False)
        except ExportError:
            raise
        except (zipfile.BadZipFile, EOFError, OSError, ValueError, TypeError, NotImplementedError,
                RuntimeError) as exc:         # a corrupt member, a bad CRC, a truncated stream
            raise fail(f"the member {key} cannot be read: {type(exc).__name__}: {exc}") from None
    return arrays


def _kind_words(kinds: str) -> str:
    if kinds == "U":
        return "text (unicode strings)"
    if kinds == "iu":
        return "integers"
    return "real numbers (float or integer; no complex, text or objects)"


def _finite(values: np.ndarray, key: str, fail: Callable[[str], ExportError]) -> None:
    bad = np.argwhere(~np.isfinite(values.astype(float)))
    if bad.size:
        where = ", ".join(str(int(i)) for i in bad[0])
        raise fail(f"{key}[{where}] is {values[tuple(bad[0])]}; numbers must be finite")


def _dense(arrays: dict[str, np.ndarray], key: str, shape: tuple[int, int],
           fail: Callable[[str], ExportError]) -> np.ndarray:
    M = arrays[key]
    if M.shape != shape:
        raise fail(f"{key} has shape {M.shape}; the names give {shape}")
    _finite(M, key, fail)
    return M.astype(float)


def _sparse(arrays: dict[str, np.ndarray], key: str, shape: tuple[int, int],
            fail: Callable[[str], ExportError]) -> Any:
    import scipy.sparse

    data, indices, indptr, dims = (arrays[f"{key}_{part}"] for part in _SPARSE_PARTS)
    if dims.shape != (2,) or tuple(int(v) for v in dims) != shape:
        raise fail(f"{key}_shape is {dims.tolist()}; the names give {list(shape)}")
    if indptr.shape != (shape[0] + 1,) or data.shape != indices.shape:
        raise fail(f"malformed sparse matrix {key}: {key}_indptr must have {shape[0] + 1} entries "
                   f"(got {indptr.shape[0]}) and {key}_data as many as {key}_indices "
                   f"({data.shape[0]} and {indices.shape[0]})")
    if (indices.size and (indices.min() < 0 or indices.max() >= max(shape[1], 1))) or \
            (indptr.size and (indptr[0] != 0 or indptr[-1] != indices.size or np.any(np.diff(indptr) < 0))):
        raise fail(f"malformed sparse matrix {key}: {key}_indices must lie in [0, {shape[1]}) and "
                   f"{key}_indptr rise from 0 to {indices.size}")
    _finite(data, f"{key}_data", fail)
    try:
        M = scipy.sparse.csr_array((data.astype(float), indices.astype(np.int64), indptr.astype(np.int64)),
                                   shape=shape)
        M.check_format(full_check=True)
    except (TypeError, ValueError) as exc:
        raise fail(f"malformed sparse matrix {key} ({key}_data, {key}_indices, {key}_indptr, "
                   f"{key}_shape): {exc}") from None
    return M
