"""Issue 16, item 1: sparse numeric plants.

Expectations come from outside the code under test: closed forms derived in
the tests from Newton's equations, the eigenvalues of a tridiagonal Toeplitz
matrix, numpy's dense eigenvalues of the dense plant's ``A``, scipy's own
readers of the exported files; the dense plant (the path that existed
before) is the reference for chains and grids too big to write by hand.
"""

from __future__ import annotations

import pickle
import warnings

import numpy as np
import pytest
import scipy.io
import scipy.sparse

import bondgraph as bg
import bondgraph.numeric.plant as plant_module
import bondgraph.numeric.sparse as sparse_module
from bondgraph.errors import BondGraphError
from bondgraph.export import ExportError, export_json, export_mat, export_npz, load_npz
from bondgraph.numeric import (DenseConversionError, DenseConversionWarning, NumericError,
                               NumericStateSpace, SparseBatchStateSpace, compile_plant)
from bondgraph.numeric import _linalg

OMEGA = np.logspace(-2, 1.5, 23)


def chain(n: int, name: str = "chain"):
    """``n`` masses ``m_i`` with dampers ``b_i`` to ground, springs ``k_i`` (stiffness)
    between neighbours, a force ``F`` on the first mass; output the last velocity."""
    g = bg.BondGraph(f"{name}{n}")
    g.add(bg.Se("F"))
    prev = None
    for i in range(n):
        v = bg.One(f"v{i}")
        g.add(v, bg.I(f"m{i}"), bg.R(f"b{i}"))
        g.connect(v, f"m{i}")
        g.connect(v, f"b{i}")
        if prev is None:
            g.connect("F", v)
        else:
            s = bg.Zero(f"s{i}")
            g.add(s, bg.C(f"k{i}", stiffness=f"k{i}"))
            g.connect(prev, s)
            g.connect(s, v)
            g.connect(s, f"k{i}")
        prev = v
    return bg.derive(g, outputs={"v_last": bg.flow(f"m{n - 1}")})


def grid(rows: int, cols: int):
    """A ``rows x cols`` grid of masses (dampers to ground) with springs between
    horizontal and vertical neighbours; force on mass (0, 0); outputs two velocities."""
    g = bg.BondGraph("grid")
    g.add(bg.Se("F"))
    for r in range(rows):
        for c in range(cols):
            v = bg.One(f"v{r}_{c}")
            g.add(v, bg.I(f"m{r}_{c}"), bg.R(f"b{r}_{c}"))
            g.connect(v, f"m{r}_{c}")
            g.connect(v, f"b{r}_{c}")
    g.connect("F", "v0_0")
    for r in range(rows):
        for c in range(cols):
            for dr, dc, tag in ((0, 1, "h"), (1, 0, "v")):
                if r + dr < rows and c + dc < cols:
                    s = bg.Zero(f"s{tag}{r}_{c}")
                    g.add(s, bg.C(f"k{tag}{r}_{c}", stiffness=f"k{tag}{r}_{c}"))
                    g.connect(f"v{r}_{c}", s)
                    g.connect(s, f"v{r + dr}_{c + dc}")
                    g.connect(s, f"k{tag}{r}_{c}")
    last = f"m{rows - 1}_{cols - 1}"
    return bg.derive(g, outputs={"v_last": bg.flow(last), "v_first": bg.flow("m0_0")})


def values_for(nm) -> dict:
    """Distinct positive values: masses ~1, dampers ~0.05, springs ~4."""
    base = {"m": 1.0, "b": 0.05, "k": 4.0}
    return {name: base[name[0]] * (1.0 + 0.013 * i) for i, name in enumerate(nm.parameter_names)}


def relative_error(H, ref):
    return float(np.max(np.abs(H - ref)) / np.max(np.abs(ref)))


# ----------------------------------------------------------------------------- hand derivations
def test_two_mass_response_matches_newton():
    """m1 x1'' = F - b1 x1' - k (x1 - x2),  m2 x2'' = -b2 x2' + k (x1 - x2), so
    V2/F = s k / ((m1 s^2 + b1 s + k)(m2 s^2 + b2 s + k) - k^2)."""
    nm = compile_plant(chain(2), sparse=True)
    m1, m2, b1, b2, k = 1.5, 0.7, 0.3, 0.2, 9.0
    ss = nm.plant({"m0": m1, "m1": m2, "b0": b1, "b1": b2, "k1": k})
    assert ss.is_sparse and scipy.sparse.issparse(ss.A)
    s = 1j * OMEGA
    expected = s * k / ((m1 * s**2 + b1 * s + k) * (m2 * s**2 + b2 * s + k) - k**2)
    H = ss.frequency_response(OMEGA)
    assert H.shape == (OMEGA.size, 1, 1)
    np.testing.assert_allclose(H[:, 0, 0], expected, rtol=1e-10)


def test_input_derivative_plant_is_sparse_too():
    """Sf v drives a mass m and a damper b on one junction: F = m dv/dt + b v, H(s) = m s + b."""
    g = bg.BondGraph("shaker")
    g.add(bg.Sf("v"), bg.One("j"), bg.I("m"), bg.R("b"))
    for tail, head in [("v", "j"), ("j", "m"), ("j", "b")]:
        g.connect(tail, head)
    ss = compile_plant(bg.derive(g, outputs={"F": bg.effort(1)})).plant({"m": 2.0, "b": 0.5},
                                                                         sparse=True)
    assert ss.is_sparse and not ss.is_proper
    np.testing.assert_allclose(ss.frequency_response(OMEGA)[:, 0, 0], 2.0 * 1j * OMEGA + 0.5,
                               rtol=1e-12)


def test_nearest_eigenvalues_of_a_tridiagonal_toeplitz_matrix():
    """tridiag(c, a, c) of size n has eigenvalues a + 2 c cos(j pi / (n + 1))."""
    n, a, c = 300, -1.0, 0.7
    A = scipy.sparse.diags([np.full(n - 1, c), np.full(n, a), np.full(n - 1, c)], [-1, 0, 1],
                           format="csr")
    ss = NumericStateSpace(A, np.ones((n, 1)), np.ones((1, n)), [[0.0]],
                           [f"x{i}" for i in range(n)], ("u",), ("y",))
    assert ss.is_sparse
    exact = a + 2 * c * np.cos(np.arange(1, n + 1) * np.pi / (n + 1))
    target = -0.3
    want = exact[np.argsort(np.abs(exact - target))[:5]]
    got = ss.eigenvalues(k=5, sigma=target)
    np.testing.assert_allclose(got.real, want, rtol=0, atol=1e-10)
    np.testing.assert_allclose(got.imag, 0.0, atol=1e-10)


def test_nearest_complex_eigenvalues_of_oscillators():
    """Blocks [[-z, w_j], [-w_j, -z]] have eigenvalues -z +- i w_j; the three nearest
    -z + 2.02 i are -z + i w_j for the w_j nearest 2.02."""
    z, w = 0.05, np.linspace(0.5, 5.0, 120)
    blocks = [scipy.sparse.csr_array(np.array([[-z, wj], [-wj, -z]])) for wj in w]
    A = scipy.sparse.block_diag(blocks, format="csr")
    n = A.shape[0]
    ss = NumericStateSpace(A, np.ones((n, 1)), np.ones((1, n)), [[0.0]],
                           [f"x{i}" for i in range(n)], ("u",), ("y",))
    want = -z + 1j * w[np.argsort(np.abs(w - 2.02))[:3]]
    np.testing.assert_allclose(ss.eigenvalues(k=3, sigma=-z + 2.02j), want, atol=1e-10)


# ----------------------------------------------------------------------------- sparse vs dense
@pytest.mark.parametrize("build", [lambda: chain(40), lambda: grid(3, 4)], ids=["chain", "grid"])
def test_sparse_response_and_eigenvalues_match_the_dense_plant(build):
    nm = compile_plant(build())
    vals = values_for(nm)
    dense, sparse = nm.plant(vals), nm.plant(vals, sparse=True)
    assert not dense.is_sparse and sparse.is_sparse            # small: dense by default
    np.testing.assert_array_equal(sparse.A.toarray(), dense.A)
    np.testing.assert_array_equal(sparse.C.toarray(), dense.C)
    Hd, Hs = dense.frequency_response(OMEGA), sparse.frequency_response(OMEGA)
    assert relative_error(Hs, Hd) < 1e-10
    # eigenvalues nearest a target: numpy's eigenvalues of the dense A, nearest picked here
    ev = np.linalg.eigvals(np.array(dense.A))
    target = -0.02 + 1.5j
    want = ev[np.argsort(np.abs(ev - target))[:6]]
    got = sparse.eigenvalues(k=6, sigma=target)
    assert got.shape == (6,)
    np.testing.assert_allclose(np.sort_complex(got), np.sort_complex(want), rtol=1e-8, atol=1e-10)
    np.testing.assert_allclose(dense.eigenvalues(k=6, sigma=target), got, rtol=1e-8, atol=1e-10)


@pytest.mark.parametrize("supernodes", [False, True], ids=["thin factors", "supernodes"])
@pytest.mark.parametrize("inputs, outputs", [(3, 1), (1, 3)], ids=["C^T solves", "B solves"])
def test_sparse_mimo_response_against_numpy_dense_solves(inputs, outputs, supernodes,
                                                         monkeypatch):
    """More inputs than outputs solves with (jw I - A)^T and C^T, more outputs with B:
    each against H = C (jw I - A)^-1 B + D by numpy's dense solver, a zero column of B
    (an input reaching no state) and a zero row of C included; refactored without
    relaxed supernodes (these thin factors) and with them (the threshold set to 0)."""
    if supernodes:
        monkeypatch.setattr(sparse_module, "THIN_FACTORS", 0)
    n = 60
    rng = np.random.default_rng(7)
    A = scipy.sparse.diags([rng.uniform(0.5, 1.5, n - 1), -rng.uniform(0.2, 2.0, n),
                            -rng.uniform(0.5, 1.5, n - 1)], [-1, 0, 1], format="csr")
    B = np.zeros((n, inputs))
    B[rng.integers(0, n, size=inputs - 1), np.arange(inputs - 1)] = 1.5   # last input: no state
    B[:, -1] = 0.0
    if inputs == 1:
        B[3, 0] = 1.0
    C = np.zeros((outputs, n))
    C[np.arange(outputs - 1 if outputs > 1 else 1), rng.integers(0, n, size=max(outputs - 1, 1))] = 0.8
    D = rng.uniform(-1, 1, (outputs, inputs))
    ss = NumericStateSpace(A, scipy.sparse.csr_array(B), scipy.sparse.csr_array(C), D,
                           [f"x{i}" for i in range(n)], [f"u{j}" for j in range(inputs)],
                           [f"y{i}" for i in range(outputs)])
    assert ss.is_sparse
    dense_A = A.toarray()
    want = np.array([C @ np.linalg.solve(1j * w * np.eye(n) - dense_A, B) + D for w in OMEGA])
    got = ss.frequency_response(OMEGA)
    assert ss._solver()._tuning == ({} if supernodes else {"relax": 1, "panel_size": 1})
    assert got.shape == (OMEGA.size, outputs, inputs)
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-14)


def test_dense_response_in_small_chunks_is_the_same(monkeypatch):
    """Chunking frequencies (here two at a time) changes memory, not the numbers:
    checked against the two-mass closed form."""
    monkeypatch.setattr(_linalg, "_CHUNK_ENTRIES", 40)       # a 4-state plant: 2 frequencies
    m1, m2, b1, b2, k = 1.0, 2.0, 0.1, 0.4, 3.0
    ss = compile_plant(chain(2)).plant({"m0": m1, "m1": m2, "b0": b1, "b1": b2, "k1": k})
    assert list(_linalg._blocks(1, 5, 3)) == [(slice(0, 1), slice(0, 4)), (slice(0, 1), slice(4, 5))]
    s = 1j * OMEGA
    expected = s * k / ((m1 * s**2 + b1 * s + k) * (m2 * s**2 + b2 * s + k) - k**2)
    np.testing.assert_allclose(ss.frequency_response(OMEGA)[:, 0, 0], expected, rtol=1e-10)


# ----------------------------------------------------------------------------- size
def test_a_2000_cell_chain_plant_stores_order_n_nonzeros():
    model = chain(2000)
    nm = compile_plant(model)
    n = len(model.states)
    assert n == 3999
    assert nm.nnz <= 5 * n + 10
    ss = nm.plant(values_for(nm))
    assert ss.is_sparse                                          # above the threshold
    assert ss.A.nnz <= 5 * n and ss.B.nnz <= 2 and ss.C.nnz <= 2
    # each mass row: its damper and up to two springs; each spring row: two masses
    assert np.max(np.diff(ss.A.indptr)) <= 3
    H = ss.frequency_response([0.0, 0.5])
    assert np.isfinite(H).all()


def test_the_threshold_chooses_and_sparse_overrides(monkeypatch):
    model = chain(4)                                             # 7 states
    assert compile_plant(model).plant(values_for(compile_plant(model))).is_sparse is False
    monkeypatch.setattr(plant_module, "SPARSE_THRESHOLD", 6)
    nm = compile_plant(model)
    vals = values_for(nm)
    assert nm.plant(vals).is_sparse and isinstance(nm.batch(vals), SparseBatchStateSpace)
    assert not nm.plant(vals, sparse=False).is_sparse
    assert not compile_plant(model, sparse=False).plant(vals).is_sparse
    monkeypatch.setattr(plant_module, "SPARSE_THRESHOLD", 7)
    assert not compile_plant(model).plant(vals).is_sparse       # more than 7 states: sparse
    assert compile_plant(model, sparse=True).plant(vals).is_sparse
    with pytest.raises(NumericError, match="sparse must be True, False or None"):
        nm.plant(vals, sparse="yes")


# ----------------------------------------------------------------------------- dense conversions
def test_to_control_warns_or_refuses_as_asked():
    nm = compile_plant(chain(3), sparse=True)
    ss = nm.plant(values_for(nm))
    with pytest.warns(DenseConversionWarning, match=r"5 states.*about \d+ B of memory"):
        sys = ss.to_control()
    np.testing.assert_array_equal(sys.A, ss.A.toarray())
    with pytest.raises(DenseConversionError, match=r"dense='refuse'") as err:
        ss.to_control(dense="refuse")
    assert isinstance(err.value, BondGraphError)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ss.to_control(dense="allow")
        ss.eigenvalues(k=2)                                      # shift-invert: no dense A
    with pytest.warns(DenseConversionWarning, match="all eigenvalues"):
        ev = ss.eigenvalues()
    np.testing.assert_allclose(ev, np.sort_complex(np.linalg.eigvals(ss.A.toarray())))
    with pytest.raises(DenseConversionError):
        ss.to_scipy(dense="refuse")
    with pytest.raises(NumericError, match="dense= must be one of"):
        ss.to_control(dense="sometimes")
    with pytest.raises(NumericError, match="k must be an integer from 1"):
        ss.eigenvalues(k=0)


# ----------------------------------------------------------------------------- export
def test_mat_and_npz_keep_the_matrices_sparse(tmp_path):
    nm = compile_plant(chain(30), sparse=True)
    ss = nm.plant(values_for(nm))
    export_mat(ss, tmp_path / "p.mat")
    m = scipy.io.loadmat(tmp_path / "p.mat")
    for key in "ABCD":
        assert scipy.sparse.issparse(m[key]), key
        np.testing.assert_array_equal(m[key].toarray(), getattr(ss, key).toarray())
    export_npz(ss, tmp_path / "p.npz")
    with np.load(tmp_path / "p.npz") as z:
        assert "A" not in z.files
        A = scipy.sparse.csr_array((z["A_data"], z["A_indices"], z["A_indptr"]),
                                   shape=tuple(z["A_shape"]))
        np.testing.assert_array_equal(A.toarray(), ss.A.toarray())
    back = load_npz(tmp_path / "p.npz")
    assert back.is_sparse and back.state_names == ss.state_names
    assert dict(back.parameters) == dict(ss.parameters) and back.name == ss.name
    for key in "ABCD":
        np.testing.assert_array_equal(getattr(back, key).toarray(), getattr(ss, key).toarray())
    dense = nm.plant(values_for(nm), sparse=False)
    export_npz(dense, tmp_path / "d.npz")
    assert not load_npz(tmp_path / "d.npz").is_sparse
    # JSON is dense: a small sparse plant is expanded, a large one refused
    export_json(ss, tmp_path / "p.json")
    assert bg.export.load_json(tmp_path / "p.json").A.tolist() == ss.A.toarray().tolist()
    big = NumericStateSpace(scipy.sparse.eye_array(600, format="csr"), np.zeros((600, 1)),
                            np.zeros((1, 600)), [[0.0]], [f"x{i}" for i in range(600)], ("u",),
                            ("y",), name="big")
    with pytest.raises(ExportError, match="sparse with 600 states.*write .mat or .npz"):
        export_json(big, tmp_path / "big.json")
    assert not (tmp_path / "big.json").exists()


def test_load_npz_names_what_is_missing(tmp_path):
    np.savez(tmp_path / "x.npz", A=np.zeros((1, 1)))
    with pytest.raises(ExportError, match="not a bondgraph-statespace archive"):
        load_npz(tmp_path / "x.npz")


# ----------------------------------------------------------------------------- batches
def test_sparse_batch_matches_individual_plants():
    nm = compile_plant(grid(2, 3))
    base = values_for(nm)
    rows = [dict(base), {**base, "m0_0": 2.0, "kh0_0": 1.0}, {**base, "b1_2": 0.4}]
    batch = nm.batch({k: [r[k] for r in rows] for k in base}, sparse=True)
    assert isinstance(batch, SparseBatchStateSpace) and len(batch) == 3
    assert batch.values.shape == (3, nm.nnz) and not batch.values.flags.writeable
    H = batch.frequency_response(OMEGA)
    ev = batch.eigenvalues(k=3, sigma=-0.01 + 2j)
    dense_batch = batch.to_dense()
    for i, row in enumerate(rows):
        one = nm.plant(row, sparse=True)
        np.testing.assert_array_equal(batch[i].A.toarray(), one.A.toarray())
        assert dict(batch[i].parameters) == dict(one.parameters)
        np.testing.assert_allclose(H[i], one.frequency_response(OMEGA), rtol=1e-12)
        np.testing.assert_allclose(ev[i], one.eigenvalues(k=3, sigma=-0.01 + 2j), rtol=1e-8)
        np.testing.assert_array_equal(dense_batch.A[i], one.A.toarray())
    assert relative_error(H, nm.batch({k: [r[k] for r in rows] for k in base},
                                      sparse=False).frequency_response(OMEGA)) < 1e-10


# ----------------------------------------------------------------------------- pickle
def test_sparse_objects_pickle_to_identical_numbers():
    nm = compile_plant(chain(12), sparse=True)
    vals = values_for(nm)
    nm2 = pickle.loads(pickle.dumps(nm))
    ss, ss2 = nm.plant(vals), nm2.plant(vals)
    assert ss2.is_sparse
    for key in "ABCD":
        np.testing.assert_array_equal(getattr(ss2, key).toarray(), getattr(ss, key).toarray())
    ss3 = pickle.loads(pickle.dumps(ss))
    assert ss3.is_sparse and not ss3.A.data.flags.writeable
    np.testing.assert_array_equal(ss3.frequency_response(OMEGA), ss.frequency_response(OMEGA))
    batch = nm.batch({k: [v, 1.1 * v] for k, v in vals.items()})
    back = pickle.loads(pickle.dumps(batch))
    assert isinstance(back, SparseBatchStateSpace) and not back.values.flags.writeable
    np.testing.assert_array_equal(back.values, batch.values)
    assert back.patterns == batch.patterns
    np.testing.assert_array_equal(back.frequency_response(OMEGA), batch.frequency_response(OMEGA))
