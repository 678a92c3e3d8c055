"""The ends and foundations of the FE models as objects: one class per kind, the mirror in one place.

Checks: each end's frequency-domain contribution against the model that carries it (a 0-bay
model closed by two ends is the paper's Sec. 5.3 pair), the mirror as a similarity with
diag(1, -1), the factory's rules, and the layout rule that no code outside ``fe/ends.py``
dispatches on an end's name.
"""

import ast
import dataclasses
import pathlib

import numpy as np
import pytest

import semitrack as st
from semitrack.fe.ends import (
    END_NAMES,
    EXACT,
    FREE,
    PINNED,
    BoundaryEnd,
    EquivalentEnd,
    make_end,
    mirror,
    mirrored,
    model_ends,
)
from semitrack.fe.supports import FlexibleSlabs, RigidFoundation, SleepersOnBallast, foundation_of

PACKAGE = pathlib.Path(st.__file__).parent


def test_the_mirror_is_a_similarity_with_diag_1_minus_1():
    rng = np.random.default_rng(0)
    X = rng.standard_normal((3, 4, 4))
    S = np.diag([1.0, -1.0, 1.0, 1.0])
    np.testing.assert_array_equal(mirrored(X, "left"), S @ X @ S)
    assert mirrored(X, "right") is X
    np.testing.assert_array_equal(mirror("left") @ X[0, :2, :2] @ mirror("left"), mirrored(X[0, :2, :2], "left"))


def test_each_end_adds_what_its_model_assembles(paper_fits):
    """Z of a 0-bay model with two equal ends is the sum of their end blocks on the shared node:
    the exact, boundary and equivalent ends' dynamic_stiffness agree with the model's own Z."""
    track = st.slab_track()
    f = np.array([50.0, 400.0])
    omega = 2 * np.pi * f
    bnd = st.fit_boundary(track, n_poles=12)
    for end in (EXACT, BoundaryEnd(boundary=bnd)):
        model = st.TruncatedTrack(track, 0, end)
        Z = np.array([model.dynamic_stiffness(x).toarray() for x in f])
        expected = end.dynamic_stiffness(track, omega, "left") + end.dynamic_stiffness(track, omega, "right")
        np.testing.assert_allclose(Z, expected, rtol=1e-12)
    system = paper_fits["slab"].system
    model = st.TruncatedTrack(track, 0, EquivalentEnd(equivalent=system))
    assert model.n_dof == 2 + 2 * (system.n_dof - 2)


def test_the_factory_and_its_rules():
    assert make_end("pinned") == PINNED and make_end("free") == FREE and set(END_NAMES) >= {"exact", "boundary"}
    with pytest.raises(TypeError, match="system must be an EquivalentSystem for an 'equivalent' end"):
        make_end("equivalent")
    with pytest.raises(ValueError, match="system is only used with an 'equivalent' or 'boundary' end"):
        make_end("exact", st.paper_table4())
    with pytest.raises(ValueError, match="one system cannot close both"):
        model_ends("equivalent", "boundary", st.paper_table4())
    with pytest.raises(ValueError, match=r"a model with zero bays \(n_left = n_right = 0\) needs 'equivalent', "
                                         r"'boundary', 'exact' ends"):
        model_ends("pinned", "exact", n_bays=0)
    ends = model_ends(PINNED, "equivalent", st.paper_table4())
    assert ends["left"] is PINNED and isinstance(ends["right"], EquivalentEnd)


def test_foundations():
    assert isinstance(foundation_of(st.slab_track()), RigidFoundation)
    assert isinstance(foundation_of(st.ballasted_track()), SleepersOnBallast)
    assert SleepersOnBallast().n_dofs(7) == 7 and RigidFoundation().n_dofs(7) == 0
    floating = st.example_track("floating-slab")
    assert isinstance(foundation_of(floating), FlexibleSlabs)
    with pytest.raises(ValueError, match="at slab joints"):
        foundation_of(floating.replace(slab=dataclasses.replace(floating.slab, cut="centre")))


def _string_constants(path: pathlib.Path):
    """Non-docstring string constants of a module, with their lines."""
    tree = ast.parse(path.read_text())
    docstrings = {id(node.body[0].value) for node in ast.walk(tree)
                  if isinstance(node, (ast.Module, ast.FunctionDef, ast.ClassDef, ast.AsyncFunctionDef))
                  and node.body and isinstance(node.body[0], ast.Expr) and isinstance(node.body[0].value, ast.Constant)}
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docstrings:
            yield node.value, node.lineno


@pytest.mark.parametrize("path", sorted([*(PACKAGE / "fe").glob("*.py"), *(PACKAGE / "interaction").glob("*.py"),
                                         *(PACKAGE / "paper").glob("*.py"),
                                         *(PACKAGE / "plotting").glob("*.py"), PACKAGE / "cli.py"]),
                         ids=lambda p: f"{p.parent.name}/{p.name}")
def test_no_end_name_is_spelled_outside_the_end_classes(path):
    """The end kinds are classes: no FE or study code compares, passes or looks up an end by its
    name (the name is each class's ``name``; users' strings go through ``make_end``)."""
    if path.name == "ends.py":
        return
    found = [(value, line) for value, line in _string_constants(path) if value in END_NAMES]
    assert not found, f"{path.name} spells end names {found}"


def test_no_private_name_is_imported_across_modules():
    """``from .x import _y`` ties two modules' insides together: a shared helper is public where it lives."""
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and (node.level or (node.module or "").startswith("semitrack")):
                found += [f"{path.relative_to(PACKAGE)}:{node.lineno} {a.name}" for a in node.names
                          if a.name.startswith("_") and not a.name.startswith("__")]
    assert not found, found
