"""Issue 16, item 2: every compiled object pickles, and a round trip gives the same numbers.

Sparse plants (``scipy.sparse`` CSR matrices) and :class:`SparseBatchStateSpace`
(patterns and a read-only ``(P, nnz)`` value array) too (item 1).

``NumericModel`` and ``NumericDynamics`` travel as their model and
expressions and are lambdified again on first use after loading (through a
per-process cache); ``NumericStateSpace``, ``BatchStateSpace`` and
``SimulationResult`` keep read-only arrays and a read-only parameter
mapping.  "Same numbers" is bit for bit (``np.array_equal``), here and in
fresh worker processes (a spawned ``ProcessPoolExecutor(2)``: nothing is
inherited from this process, so the workers really recompile).
"""

from __future__ import annotations

import multiprocessing
import operator
import pickle
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest
import sympy
from sympy.utilities.lambdify import implemented_function

import bondgraph as bg
from bondgraph.numeric import (BatchStateSpace, NotPicklableError, NumericStateSpace,
                               SimulationResult, SparseBatchStateSpace, compile_dynamics,
                               compile_plant, simulate)
from bondgraph.numeric import _compile

VALUES = {"Ra": 2.0, "La": 0.5, "K": 0.1, "J": 0.02, "b": 0.2}
BATCH = {"Ra": [1.0, 2.0, 3.0], "La": 0.5, "K": [0.1, 0.2, 0.3], "J": 0.02, "b": 0.2}


def dc_motor():
    g = bg.BondGraph("dc_motor")
    V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
    g.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.I("J"), bg.R("b"))
    for tail, head in [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "J"), (w, "b")]:
        g.connect(tail, head)
    return bg.derive(g, outputs={"omega": bg.flow("J"), "theta": bg.displacement("J")})


def dc_motor_sqrt():
    """dc_motor with a damping ``b = sqrt(Ra)``: entries that are not monomials are lambdified."""
    g = bg.BondGraph("dc_motor")
    V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
    g.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.I("J"),
          bg.R("b", sympy.sqrt(sympy.Symbol("Ra", positive=True)) + sympy.Symbol("b", positive=True)))
    for tail, head in [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "J"), (w, "b")]:
        g.connect(tail, head)
    return bg.derive(g, outputs={"omega": bg.flow("J"), "theta": bg.displacement("J")})


def shaker():
    """A velocity source on a mass and a damper: an improper plant (F = (m s + b) vr)."""
    g = bg.BondGraph("shaker")
    g.add(bg.Sf("vr"), bg.One("j"), bg.I("m"), bg.R("b"))
    for t, h in [("vr", "j"), ("j", "m"), ("j", "b")]:
        g.connect(t, h)
    return bg.derive(g, outputs={"F": bg.effort("vr")})


def duffing():
    k, k3 = sympy.symbols("k k3", positive=True)
    g = bg.BondGraph("duffing")
    F, v = bg.Se("F"), bg.One("v")
    g.add(F, v, bg.I("m"), bg.R("b"), bg.C("s", law=k * bg.q + k3 * bg.q**3))
    for tail, head in [(F, v), (v, "m"), (v, "b"), (v, "s")]:
        g.connect(tail, head)
    return bg.derive(g, outputs={"x": bg.displacement("s")})


DUFFING = {"m": 1.0, "b": 0.3, "k": 2.0, "k3": 0.5}


def roundtrip(obj):
    return pickle.loads(pickle.dumps(obj))


def _same_matrix(Ma, Mb) -> bool:
    """Equal bit for bit, of the same kind (dense or CSR), and read-only."""
    if a_sparse := hasattr(Ma, "tocsr"):
        return (hasattr(Mb, "tocsr") and np.array_equal(Ma.indptr, Mb.indptr)
                and np.array_equal(Ma.indices, Mb.indices) and np.array_equal(Ma.data, Mb.data)
                and not Mb.data.flags.writeable)
    return not a_sparse and np.array_equal(Ma, Mb) and not Mb.flags.writeable


def same_plant(a: NumericStateSpace, b: NumericStateSpace) -> None:
    assert a.is_sparse == b.is_sparse
    for name in "ABCD":
        assert _same_matrix(getattr(a, name), getattr(b, name)), name
    assert len(a.D_derivatives) == len(b.D_derivatives)
    for Ma, Mb in zip(a.D_derivatives + a.state_shift, b.D_derivatives + b.state_shift):
        assert _same_matrix(Ma, Mb)
    assert (a.state_names, a.input_names, a.output_names, a.name) == \
        (b.state_names, b.input_names, b.output_names, b.name)
    assert dict(a.parameters) == dict(b.parameters)


def same_result(a: SimulationResult, b: SimulationResult) -> None:
    for name in ("t", "x", "y", "u"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
        assert not getattr(b, name).flags.writeable
    assert dict(a.parameters) == dict(b.parameters)
    assert (a.state_names, a.output_names, a.name) == (b.state_names, b.output_names, b.name)


# ------------------------------------------------------------------ in process
@pytest.mark.parametrize("build, values", [(dc_motor, VALUES), (dc_motor_sqrt, VALUES),
                                           (shaker, {"m": 2.0, "b": 0.5})])
def test_numeric_model_round_trip_recompiles_lazily_to_the_same_numbers(build, values):
    nm = compile_plant(build())
    blob = pickle.dumps(nm)
    _compile._CACHE.clear()                       # force a real recompilation on load
    back = pickle.loads(blob)
    general = back._fn.general                    # the lambdified part (None: all monomials)
    assert general is None or "not yet compiled" in repr(general)   # nothing compiled by unpickling
    assert (general is None) == (build is not dc_motor_sqrt)
    assert back.parameter_names == nm.parameter_names and back.model.name == nm.model.name
    same_plant(nm.plant(values), back.plant(values))
    assert general is None or "not yet compiled" not in repr(general)
    batch = {k: np.linspace(v, 2 * v, 4) for k, v in values.items()}
    a, b = nm.batch(batch), back.batch(batch)
    for name in ("A", "B", "C", "D", "parameter_values"):
        assert np.array_equal(getattr(a, name), getattr(b, name))


def test_loading_twice_compiles_once_through_the_cache():
    nm = compile_plant(dc_motor_sqrt())
    blob = pickle.dumps(nm)
    _compile._CACHE.clear()
    one, two = pickle.loads(blob), pickle.loads(blob)
    one.plant(VALUES), two.plant(VALUES)
    assert one._fn.general._fn is two._fn.general._fn            # the same lambdified function
    assert len(_compile._CACHE) == 1


def test_plants_and_batches_round_trip_read_only():
    nm = compile_plant(dc_motor())
    plant = nm.plant(VALUES)
    back = roundtrip(plant)
    same_plant(plant, back)
    assert type(back.parameters).__name__ == "mappingproxy"
    batch = nm.batch(BATCH)
    bb = roundtrip(batch)
    assert isinstance(bb, BatchStateSpace) and len(bb) == 3
    for name in ("A", "B", "C", "D", "parameter_values"):
        assert np.array_equal(getattr(batch, name), getattr(bb, name))
        assert not getattr(bb, name).flags.writeable
    same_plant(batch[1], bb[1])
    improper = compile_plant(shaker()).plant({"m": 2.0, "b": 0.5})
    assert not improper.is_proper
    same_plant(improper, roundtrip(improper))


@pytest.mark.parametrize("build, values", [(dc_motor, VALUES), (shaker, {"m": 2.0, "b": 0.5})])
def test_sparse_plants_and_batches_round_trip(build, values):
    nm = compile_plant(build(), sparse=True)
    back_nm = roundtrip(nm)
    plant = nm.plant(values)
    assert plant.is_sparse
    same_plant(plant, back_nm.plant(values))
    same_plant(plant, roundtrip(plant))
    omega = [0.0, 1.0, 10.0]
    assert np.array_equal(plant.frequency_response(omega), roundtrip(plant).frequency_response(omega),
                          equal_nan=True)
    batch = nm.batch({k: np.linspace(v, 2 * v, 3) for k, v in values.items()})
    bb = roundtrip(batch)
    assert isinstance(bb, SparseBatchStateSpace) and len(bb) == 3 and bb.patterns == batch.patterns
    for name in ("values", "parameter_values"):
        assert np.array_equal(getattr(batch, name), getattr(bb, name))
        assert not getattr(bb, name).flags.writeable
    same_plant(batch[2], bb[2])


def test_dynamics_and_simulation_results_round_trip():
    dyn = compile_dynamics(duffing())
    blob = pickle.dumps(dyn)
    _compile._CACHE.clear()
    back = pickle.loads(blob)
    kw = dict(x0={"q_s": 1.0}, u=lambda t: [np.sin(t)], t_eval=np.linspace(0, 5, 11))
    a, b = simulate(dyn, DUFFING, (0.0, 5.0), **kw), simulate(back, DUFFING, (0.0, 5.0), **kw)
    same_result(a, b)
    same_result(a, roundtrip(a))
    assert type(roundtrip(a).parameters).__name__ == "mappingproxy"


def test_a_law_calling_a_python_function_is_refused_by_name():
    sat = implemented_function("sat", np.tanh)
    g = bg.BondGraph("friction")
    F, v = bg.Se("F"), bg.One("v")
    g.add(F, v, bg.I("m"), bg.R("Rf", law=sat(bg.f)))
    for tail, head in [(F, v), (v, "m"), (v, "Rf")]:
        g.connect(tail, head)
    dyn = compile_dynamics(bg.derive(g, outputs={"v": bg.flow("m")}))
    with pytest.raises(NotPicklableError, match=r"friction.*sat") as info:
        pickle.dumps(dyn)
    assert isinstance(info.value, pickle.PicklingError) and isinstance(info.value, bg.BondGraphError)


# ------------------------------------------------------------------ in fresh processes
def test_everything_crosses_a_process_pool_unchanged():
    nm, dyn = compile_plant(dc_motor()), compile_dynamics(duffing())
    plant, batch = nm.plant(VALUES), nm.batch(BATCH)
    kw = dict(x0={"q_s": 1.0}, u=[0.5], t_eval=np.linspace(0, 2, 5))
    result = simulate(dyn, DUFFING, (0.0, 2.0), **kw)
    omega = [0.0, 1.0, 10.0]
    with ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("spawn")) as pool:
        remote_plant = pool.submit(operator.methodcaller("plant", VALUES), nm)
        remote_batch = pool.submit(operator.methodcaller("batch", BATCH), nm)
        remote_result = pool.submit(simulate, dyn, DUFFING, (0.0, 2.0), **kw)
        remote_frf = pool.submit(operator.methodcaller("frequency_response", omega), plant)
        remote_batch_frf = pool.submit(operator.methodcaller("frequency_response", omega), batch)
        remote_history = pool.submit(operator.itemgetter("x"), result)
        same_plant(plant, remote_plant.result())
        for name in ("A", "B", "C", "D"):
            assert np.array_equal(getattr(batch, name), getattr(remote_batch.result(), name))
        same_result(result, remote_result.result())
        assert np.array_equal(plant.frequency_response(omega), remote_frf.result(), equal_nan=True)
        assert np.array_equal(batch.frequency_response(omega), remote_batch_frf.result(), equal_nan=True)
        assert np.array_equal(result["x"], remote_history.result())


def test_sparse_objects_cross_a_process_pool_unchanged():
    nm = compile_plant(dc_motor(), sparse=True)
    plant, batch = nm.plant(VALUES), nm.batch(BATCH)
    omega = [0.0, 1.0, 10.0]
    with ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("spawn")) as pool:
        remote_plant = pool.submit(operator.methodcaller("plant", VALUES), nm)
        remote_batch = pool.submit(operator.methodcaller("batch", BATCH), nm)
        remote_frf = pool.submit(operator.methodcaller("frequency_response", omega), batch)
        same_plant(plant, remote_plant.result())
        assert np.array_equal(batch.values, remote_batch.result().values)
        assert np.array_equal(batch.frequency_response(omega), remote_frf.result(), equal_nan=True)
