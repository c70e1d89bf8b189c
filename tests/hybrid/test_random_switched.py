"""Differential check: every mode of random switched graphs against the independent reference.

Two switches are hung on random junctions of a random linear graph
(``tests/verification/generator.py``).  For each of the four modes the
reference solver (``tests/verification/reference.py``, which shares no code
with bondgraph) solves the bond graph's own equations with each switch
written as the source it is in that mode (on: ``Se`` of value 0, off: ``Sf``
of value 0; as extra inputs whose columns are dropped).  The mode's
``Model`` from :class:`bondgraph.hybrid.SwitchedModel` must give the same
transfer matrix at two random ``s``; a mode the reference finds ill-posed
must be refused (``ModeError``).  ``bench/hybrid_random.py`` runs more seeds.
"""

import random
import sys
import warnings
from dataclasses import replace
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from verification.generator import _compare, _numeric_at, _signal_expr, generate, values  # noqa: E402
from verification.reference import Bond, Element, Reference  # noqa: E402

import bondgraph as bg  # noqa: E402
from bondgraph.hybrid import ModeError, Switch, SwitchedModel  # noqa: E402

SWITCHES = ("SWa", "SWb")


def switched(seed: int):
    """The random graph with two switches, as the reference description and as a bondgraph."""
    g = generate(seed, max_elements=12)
    rng = random.Random(seed)
    junctions = [el.name for el in g.elements if el.kind in ("Zero", "One")]
    if not junctions:
        return None
    where = [rng.choice(junctions) for _ in SWITCHES]
    first = max(b.id for b in g.bonds) + 1
    bonds = tuple(Bond(first + k, j, s) for k, (j, s) in enumerate(zip(where, SWITCHES)))
    desc = replace(g, elements=g.elements + tuple(Element(s, "Se") for s in SWITCHES),
                   bonds=g.bonds + bonds)
    ctor = {"Se": bg.Se, "Sf": bg.Sf, "I": bg.I, "C": bg.C, "R": bg.R, "TF": bg.TF, "GY": bg.GY,
            "Zero": bg.Zero, "One": bg.One}
    graph = bg.BondGraph(g.name)
    graph.add(*(ctor[el.kind](el.name) for el in g.elements), *(Switch(s) for s in SWITCHES))
    number = {b.id: graph.connect(b.tail, b.head).number for b in desc.bonds}
    outputs = {o.name: _signal_expr(bg, g, o, number) for o in g.outputs}
    return g, desc, SwitchedModel(graph, outputs)


def check_seed(seed: int) -> dict:
    """Compare every mode of seed ``seed``; returns counts by outcome (raises on a wrong one)."""
    made = switched(seed)
    counts = {"agree": 0, "refused-ill-posed": 0, "name-clash": 0, "skipped": 0}
    if made is None:
        counts["skipped"] += 1
        return counts
    g, desc, sm = made
    vals = values(g)
    in_names = [el.name for el in g.sources]
    out_names = [o.name for o in g.outputs]
    rng = random.Random(seed + 1)
    for mode in sm.all_modes:
        kinds = {s: ("Se" if mode.is_on(s) else "Sf") for s in SWITCHES}
        ref_desc = replace(desc, elements=tuple(replace(el, kind=kinds.get(el.name, el.kind))
                                                for el in desc.elements))
        ref = Reference(ref_desc)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                model = sm.derived(mode).user
            except ModeError:
                assert not ref.well_posed, f"seed {seed}, mode ({mode}): well-posed but refused"
                counts["refused-ill-posed"] += 1
                continue
            except bg.NameClashError:      # the generator's name clashes, refused as by derive
                counts["name-clash"] += 1
                continue
        assert ref.well_posed, f"seed {seed}, mode ({mode}): ill-posed but derived"
        if not out_names or not in_names:
            counts["skipped"] += 1
            continue
        s_list = ref.pick_s(rng, 2)
        cols = [ref.input_names.index(u) for u in in_names]
        G_ref = [ref.evaluate(s)[:, cols] for s in s_list]
        nm = bg.compile_plant(model)
        plant = nm.plant({k: vals[k] for k in nm.parameter_names})
        at, _, _ = _numeric_at(plant, s_list, in_names, out_names)
        for s, Gr, (G, bound) in zip(s_list, G_ref, at):
            ok, rel, _ = _compare(Gr, G, bound)
            assert ok, f"seed {seed}, mode ({mode}), s = {s}: relative error {rel:.3g}"
        counts["agree"] += 1
    return counts


@pytest.mark.parametrize("seed", [0, 1, 3, 4, 11, 27], ids=lambda s: f"seed{s}")
def test_random_switched_modes_agree_with_the_reference(seed):
    counts = check_seed(seed)
    assert counts["agree"] >= 1
