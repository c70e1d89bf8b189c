"""The restructuring kept every public name and every old module path (issue 21).

The names are listed here as they were before the stage folders (the
``bondgraph.__all__`` of the last release and the names users imported from
the modules that moved); each must still import, the old module paths with a
``DeprecationWarning`` that names the new one.
"""

from __future__ import annotations

import importlib
import subprocess
import sys
import warnings

import pytest

import bondgraph

#: ``bondgraph.__all__`` before the restructuring
PUBLIC = """BondGraph Bond FlatGraph flatten Element Se Sf I C R TF GY MTF MGY Zero One Port IField
CField ICField RField FieldError AugmentedBondGraph CausalBond assign_causality derive Model
SymbolicStateSpace Signal effort flow displacement momentum p q e f t BondGraphError
ModelStructureError DuplicateNameError UnknownElementError PortError ParameterError LawError
CausalityError CausalityConflictError AlgebraicLoopError OutputError NonlinearModelError
NameClashError BondGraphWarning ModelDefinition ModelFileError load_model compile_plant
numeric_plant NumericModel NumericStateSpace BatchStateSpace simulate SimulationResult
to_nonlinear_iosys ParameterValueError MissingValueError ImproperPlantError ExportError draw
sweep sensitivity""".split()

#: old module path -> (new module path, names users imported from it)
OLD_PATHS = {
    "bondgraph.protocol": ("bondgraph.elements.protocol",
                           ["ARBITRARY", "DERIVATIVE", "INTEGRAL", "RESISTIVE", "STORAGE",
                            "CausalPorts", "Choice", "Decision", "LocalVariables", "Element"]),
    "bondgraph.junctions": ("bondgraph.elements", ["TF", "GY", "MTF", "MGY", "Zero", "One", "Port",
                                                   "TwoPort"]),
    "bondgraph.fields": ("bondgraph.elements.fields", ["IField", "CField", "ICField", "RField",
                                                       "FieldError", "StorageField"]),
    "bondgraph.operating": ("bondgraph.linear.operating", ["Equilibrium", "EquilibriumError",
                                                           "equilibrium"]),
    "bondgraph.statespace": ("bondgraph.linear.statespace", ["SymbolicStateSpace"]),
    "bondgraph.transfer": ("bondgraph.tf", ["transfer_function", "transfer_matrix", "SymbolicTF",
                                            "NumericTF", "InvalidOptionError"]),
    "bondgraph.values": ("bondgraph._support.sympify", ["to_expr", "as_expr", "as_matrix"]),
    "bondgraph.files": ("bondgraph._support.files", ["ExportError", "atomic_write"]),
    "bondgraph.loops": ("bondgraph.equations.loops", ["solve_blocks", "SingularLoopError"]),
    "bondgraph.integrators": ("bondgraph.equations.integrators", ["state_combination"]),
    "bondgraph.control": ("bondgraph.numeric.control", ["pd_place", "pid_place", "specs_to_poles",
                                                        "minimal_realization"]),
    "bondgraph.plots": ("bondgraph.drawing.plots", ["bode", "pole_zero", "step", "impulse",
                                                    "frf_overlay", "PlotError"]),
}


@pytest.mark.parametrize("name", PUBLIC)
def test_every_public_name_is_still_importable(name):
    assert getattr(bondgraph, name) is not None
    assert name in bondgraph.__all__


@pytest.mark.parametrize("old", sorted(OLD_PATHS))
def test_old_module_paths_warn_and_work(old):
    new, names = OLD_PATHS[old]
    # a fresh interpreter: the warning is given on the first import only
    code = (f"import warnings; warnings.simplefilter('error', DeprecationWarning)\n"
            f"try:\n    import {old}\nexcept DeprecationWarning as w:\n    print(w)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.stdout.strip() == f"{old} is deprecated; import from {new}", out.stderr
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        module = importlib.import_module(old)
    assert module is importlib.import_module(new)
    for n in names:
        assert hasattr(module, n), f"{old}.{n}"


def test_public_exceptions_are_named_where_users_import_them():
    for name in ("FieldError", "ModelFileError", "ExportError", "ImproperPlantError"):
        cls = getattr(bondgraph, name)
        assert f"{cls.__module__}.{cls.__qualname__}" == f"bondgraph.{name}"
    from bondgraph import drawing, hamiltonian, identification, linear
    assert linear.EquilibriumError.__module__ == "bondgraph.linear"
    assert hamiltonian.PortHamiltonianError.__module__ == "bondgraph.hamiltonian"
    assert identification.IdentificationError.__module__ == "bondgraph.identification"
    assert drawing.DrawingError.__module__ == "bondgraph.drawing"


def test_import_bondgraph_loads_no_later_stage_by_itself():
    # the finder of old paths answers only for them: importing the package imports none
    code = ("import sys, bondgraph; "
            "print(sorted(m for m in bondgraph._support.moved.MOVED if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.stdout.strip() == "[]", out.stderr
