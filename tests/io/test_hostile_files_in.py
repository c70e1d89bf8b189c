"""Issue 23, items 1, 7, 8: data files read without trusting them (audit X02-X29, C01, C02).

Every hostile ``.npz`` or JSON plant, params or operating-point file is refused
with an ``ExportError`` / the CLI's one ``error:`` line naming the file, with
no crash (the bad-indices case and the fuzz run in a subprocess, so a
segfault fails the test instead of killing the suite), no blocking read of a
FIFO, no read of ``/dev/zero``.
"""

import os
import subprocess
import sys
import textwrap
import zipfile
from pathlib import Path

import numpy as np
import pytest

from bondgraph.export import ExportError, export_json, export_npz, load_json, load_npz
from bondgraph.numeric import NumericStateSpace

ROOT = Path(__file__).resolve().parents[2]
ENV = {**os.environ, "PYTHONPATH": str(ROOT)}


def _plant(sparse=False):
    ss = NumericStateSpace([[-1.0, 0.0], [1.0, -2.0]], [[1.0], [0.0]], [[0.0, 1.0]], [[0.0]],
                           ("x1", "x2"), ("u",), ("y",), {"k": 2.0}, "two")
    return ss.to_sparse() if sparse else ss


def _members(path):
    with np.load(path) as z:
        return {k: z[k] for k in z.files}


def _rewrite(tmp_path, sparse=False, **changes):
    good = tmp_path / "good.npz"
    export_npz(_plant(sparse), good)
    arrays = _members(good)
    arrays.update(changes)
    for key, value in changes.items():
        if value is None:
            del arrays[key]
    bad = tmp_path / "bad.npz"
    np.savez(bad, **arrays)
    return bad


def _run(code, timeout=120):
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True,
                          text=True, timeout=timeout, env=ENV, cwd=str(ROOT))


def test_bad_sparse_indices_refused_without_crash(tmp_path):
    """X17/X18: scipy does not check CSR indices; reading then touching the matrix segfaulted.

    One subprocess for every case: a crash fails this test, not the suite.
    """
    paths = []
    for k, index in enumerate([10**8, -1, 5, 2]):
        bad = _rewrite(tmp_path, sparse=True)
        arrays = _members(bad)
        arrays["A_indices"] = arrays["A_indices"].copy()
        arrays["A_indices"][0] = index
        paths.append(str(tmp_path / f"bad{k}.npz"))
        np.savez(paths[-1], **arrays)
    done = _run(f"""
        from bondgraph.export import load_npz, ExportError
        for path in {paths!r}:
            try:
                p = load_npz(path)
            except ExportError as exc:
                print("REFUSED", exc)
            else:
                print("ACCEPTED", p.A.toarray().tolist(), p.frequency_response([1.0]))
        """)
    assert done.returncode == 0, f"crashed with exit {done.returncode}: {done.stderr[-500:]}"
    lines = done.stdout.splitlines()
    assert len(lines) == 4 and all(line.startswith("REFUSED") and "A_indices" in line for line in lines)
    assert all(f"bad{k}.npz" in line for k, line in enumerate(lines))


def test_non_monotone_indptr_refused(tmp_path):
    bad = _rewrite(tmp_path, sparse=True)
    arrays = _members(bad)
    arrays["A_indptr"] = np.array([0, 3, 1])
    np.savez(bad, **arrays)
    with pytest.raises(ExportError, match="A_indptr"):
        load_npz(bad)


@pytest.mark.parametrize("content,match", [
    (b"", "not a numpy .npz archive"),
    (b"PK\x03\x04truncated", "not a numpy .npz archive"),
    (b"\x93NUMPY\x01\x00v\x00{'descr': '<f8', 'fortran_order': False, 'shape': (1,), }", "not a numpy .npz"),
], ids=["empty", "truncated-zip", "npy-not-npz"])
def test_not_an_archive(tmp_path, content, match):
    """X02-X04: EOFError, BadZipFile, TypeError escaped."""
    path = tmp_path / "p.npz"
    path.write_bytes(content)
    with pytest.raises(ExportError, match=match) as info:
        load_npz(path)
    assert str(path) in str(info.value)


def test_truncated_real_archive(tmp_path):
    path = tmp_path / "p.npz"
    export_npz(_plant(), path)
    raw = path.read_bytes()
    path.write_bytes(raw[: len(raw) // 2])
    with pytest.raises(ExportError, match="p.npz"):
        load_npz(path)


@pytest.mark.parametrize("changes,match", [
    ({"format_version": np.array(1 + 1j)}, "format_version"),
    ({"format_version": np.array("abc")}, "format_version"),
    ({"format_version": np.array(1.9)}, "format_version"),
    ({"A": np.array([[1j, 0], [0, 1]])}, r"A has dtype complex"),
    ({"A": np.array([[np.nan, 0.0], [0.0, 1.0]])}, r"A\[0, 0\] is nan"),
    ({"A": np.array([["1", "0"], ["0", "1"]])}, r"A has dtype <U1"),
    ({"parameter_values": np.array(["2"])}, "parameter_values has dtype"),
    ({"parameter_values": np.array([np.inf])}, r"parameter_values\[0\] is inf"),
    ({"state_names": np.array(["x", "x"])}, "state_names names 'x' more than once"),
    ({"state_names": np.array([1, 2])}, "state_names has dtype"),
    ({"A": np.zeros((3, 3))}, r"A has shape \(3, 3\)"),
    ({"model_name": None}, "missing arrays model_name"),
], ids=["version-complex", "version-text", "version-1.9", "complex-A", "nan-A", "text-A",
        "text-values", "inf-values", "duplicate-states", "numeric-names", "shape", "missing"])
def test_bad_members(tmp_path, changes, match):
    """X05-X09, X13, X16, X20, X22: raw errors, lost imaginary parts, NaN and text accepted."""
    bad = _rewrite(tmp_path, **changes)
    with pytest.raises(ExportError, match=match) as info:
        load_npz(bad)
    assert "bad.npz" in str(info.value)


def test_sparse_text_data_refused(tmp_path):
    bad = _rewrite(tmp_path, sparse=True)
    arrays = _members(bad)
    arrays["A_data"] = arrays["A_data"].astype(str)
    np.savez(bad, **arrays)
    with pytest.raises(ExportError, match="A_data has dtype"):
        load_npz(bad)


def test_unknown_member_is_never_decompressed(tmp_path):
    """X22: a junk member was decompressed (3 GB) before any check; now it is not even opened.

    The junk member's stored CRC is wrong: reading it would raise; the plant loads.
    """
    path = tmp_path / "p.npz"
    export_npz(_plant(), path)
    with zipfile.ZipFile(path, "a") as z:
        z.writestr("junk.npy", b"\0" * 100_000, compress_type=zipfile.ZIP_DEFLATED)
    raw = bytearray(path.read_bytes())
    # corrupt the junk member's CRC in its central directory entry and local header
    with zipfile.ZipFile(path) as z:
        info = z.getinfo("junk.npy")
    crc = info.CRC.to_bytes(4, "little")
    assert raw.count(crc) == 2
    raw = raw.replace(crc, bytes(b ^ 0xFF for b in crc))
    path.write_bytes(bytes(raw))
    back = load_npz(path)
    np.testing.assert_array_equal(back.A, [[-1.0, 0.0], [1.0, -2.0]])


def test_member_size_checked_from_header(tmp_path, monkeypatch):
    """A member larger than the budget is refused from the zip directory, before reading it."""
    import bondgraph.export.npz_read as reader

    path = tmp_path / "p.npz"
    export_npz(_plant(), path)
    monkeypatch.setattr(reader, "ARRAYS_LIMIT", 100)
    with pytest.raises(ExportError, match="decompressed, more than the 100 bytes"):
        load_npz(path)


def test_fifo_and_dev_zero_refused(tmp_path):
    """C01/C02/X29: a FIFO blocked forever; a symlink to /dev/zero read until MemoryError."""
    fifo = tmp_path / "p.npz"
    os.mkfifo(fifo)
    with pytest.raises(ExportError, match="it is a FIFO, not a regular file"):
        load_npz(fifo)
    link = tmp_path / "p.json"
    link.symlink_to("/dev/zero")
    with pytest.raises(ExportError, match="it is a character device, not a regular file"):
        load_json(link)


def test_json_plant_size_cap(tmp_path, monkeypatch):
    """X29: a 2 GB JSON plant was read whole before being refused; now the size is checked first."""
    import bondgraph._support.safe_read as safe

    path = tmp_path / "p.json"
    export_json(_plant(), path)
    monkeypatch.setattr(safe, "PLANT_LIMIT", 10)
    with pytest.raises(ExportError, match=r"p\.json' is \d[\d,]* bytes, larger than the 10 bytes"):
        load_json(path)


def test_round_trip_still_exact(tmp_path):
    for sparse in (False, True):
        path = tmp_path / f"p{sparse}.npz"
        export_npz(_plant(sparse), path)
        back = load_npz(path)
        A = back.A.toarray() if sparse else back.A
        np.testing.assert_array_equal(A, [[-1.0, 0.0], [1.0, -2.0]])
        assert back.state_names == ("x1", "x2") and dict(back.parameters) == {"k": 2.0}


MSD = """\
import bondgraph as bg

def model():
    g = bg.BondGraph("msd")
    g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b"), bg.C("c"))
    for t, h in [("F", "v"), ("v", "m"), ("v", "b"), ("v", "c")]:
        g.connect(t, h)
    return bg.ModelDefinition(g, outputs={"x": bg.displacement("c")},
                              parameters={"m": 2.0, "b": 6.0, "c": 0.25})
"""


def _cli(*argv):
    """The command line in-process (nothing here can block or crash): (exit status, stderr)."""
    import contextlib
    import io

    from bondgraph.cli import main

    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main(list(argv))
    return code, err.getvalue()


def test_cli_fifo_params_refused_naming_the_params_file(tmp_path):
    """C01: ``--params`` a FIFO blocked forever; C02: /dev/zero blamed the model file."""
    model = tmp_path / "msd.py"
    model.write_text(MSD)
    fifo = tmp_path / "p.json"
    os.mkfifo(fifo)
    code, err = _cli("export", str(model), "--params", str(fifo), "-o", str(tmp_path / "x.json"))
    assert code == 1
    assert err.startswith(f"error: cannot read params file '{fifo}': it is a FIFO")
    zero = tmp_path / "z.json"
    zero.symlink_to("/dev/zero")
    code, err = _cli("export", str(model), "--params", str(zero), "-o", str(tmp_path / "x.json"))
    assert code == 1 and "model file" not in err
    assert f"params file '{zero}': it is a character device" in err
    assert not (tmp_path / "x.json").exists()


def test_cli_operating_point_fifo_refused(tmp_path):
    model = tmp_path / "msd.py"
    model.write_text(MSD)
    fifo = tmp_path / "op.json"
    os.mkfifo(fifo)
    code, err = _cli("export", str(model), "--operating-point", str(fifo), "-o", str(tmp_path / "x.json"))
    assert code in (1, 2)
    assert f"operating-point file '{fifo}': it is a FIFO" in err


FUZZ = """
import io, os, sys, zipfile, tempfile
import numpy as np
from hypothesis import given, settings, strategies as st, HealthCheck
from bondgraph.export import ExportError, export_json, export_npz, load_json, load_npz
from bondgraph.numeric import NumericStateSpace

d = tempfile.mkdtemp()
ss = NumericStateSpace([[-1.0, 0.0], [1.0, -2.0]], [[1.0], [0.0]], [[0.0, 1.0]], [[0.0]],
                       ("x1", "x2"), ("u",), ("y",), {"k": 2.0}, "two")
seeds = {}
for name, plant in (("dense.npz", ss), ("sparse.npz", ss.to_sparse())):
    # stored, not deflated: a byte flip lands in a header or an array, not only in a stream
    path = os.path.join(d, name)
    export_npz(plant, path)
    with np.load(path) as z:
        members = {k: z[k] for k in z.files}
    buf = io.BytesIO()
    np.savez(buf, **members)
    seeds[name] = buf.getvalue()
export_json(ss, os.path.join(d, "p.json"))
seeds["p.json"] = open(os.path.join(d, "p.json"), "rb").read()

def check(name, raw):
    path = os.path.join(d, "m_" + name)
    with open(path, "wb") as fh:
        fh.write(raw)
    try:
        p = (load_json if name.endswith(".json") else load_npz)(path)
    except ExportError:
        return
    A = p.A.toarray() if p.is_sparse else p.A
    assert A.shape == (p.nstates, p.nstates) and np.isfinite(A).all()
    assert len(set(p.state_names)) == p.nstates
    p.frequency_response([1.0])

mutation = st.lists(st.tuples(st.integers(0, 10**6), st.integers(0, 255)), min_size=1, max_size=4)

@settings(max_examples=int(sys.argv[1]), deadline=None, derandomize=True,
          suppress_health_check=list(HealthCheck), database=None)
@given(st.sampled_from(sorted(seeds)), mutation, st.integers(0, 10**6))
def fuzz(name, flips, cut):
    raw = bytearray(seeds[name])
    for pos, value in flips:
        raw[pos % len(raw)] = value
    if cut % 7 == 0:
        raw = raw[: cut % len(raw)]
    check(name, bytes(raw))

fuzz()
print("FUZZ-OK")
"""


def test_fuzz_load_npz_and_load_json_in_a_subprocess():
    """Every mutated valid file gives a valid plant or an ExportError; the process never crashes."""
    done = subprocess.run([sys.executable, "-c", FUZZ, "300"], capture_output=True, text=True,
                          timeout=240, env=ENV, cwd=str(ROOT))
    assert done.returncode == 0, f"exit {done.returncode}: {done.stderr[-2000:]}"
    assert "FUZZ-OK" in done.stdout
