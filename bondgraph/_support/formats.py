"""File formats by suffix: the one table of ``bondgraph.export`` and the command line.

Kept apart from :mod:`bondgraph.export` (which loads numpy and the numeric
plants) so that ``bondgraph --help`` reads it without importing them.

Examples
--------
>>> EXPORT_FORMATS[".fmu"], FORMATS[".mat"]
('fmu', 'mat')
"""

from __future__ import annotations

__all__ = ["FORMATS", "EXPORT_FORMATS"]

#: file suffix -> format name understood by :func:`bondgraph.export.export` (numeric plants)
FORMATS = {".mat": "mat", ".npz": "npz", ".json": "json"}
#: file suffix -> every format ``bondgraph export`` writes: the plant formats above, generated
#: code (C with its header, MATLAB/Octave, Python) and FMUs; the one table the CLI reads
EXPORT_FORMATS = {**FORMATS, ".c": "c", ".m": "m", ".py": "py", ".fmu": "fmu"}
