"""The package's layers: every import points down the stack described in ARCHITECTURE.md.

Layers, lowest first: ``base`` (checks, conventions, the paper's numbers) -> ``dynamics`` (second-order
systems in time, knowing nothing of tracks) -> ``model`` ->
``methods`` -> ``equivalent`` -> ``boundary`` -> ``fe`` -> ``interaction`` -> ``studies`` -> ``paper`` -> the
top-level modules (``cli``, ``plotting`` and the flat namespace). A module may import from its own subpackage
and from lower layers only. The test reads the source with :mod:`ast`, so it also sees imports
inside functions, and it fails on a module that no layer claims, so ARCHITECTURE.md and this
table stay complete together.
"""

from __future__ import annotations

import ast
import importlib
import pathlib

import pytest

import semitrack

PACKAGE = pathlib.Path(semitrack.__file__).parent
ROOT = PACKAGE.parent.parent

LAYERS = {"base": 0, "dynamics": 1, "model": 2, "methods": 3, "equivalent": 4, "boundary": 5, "fe": 6,
          "interaction": 7, "studies": 8, "paper": 9}
TOP = 10  # cli, plotting, __init__, __main__
TOP_MODULES = {"__init__", "__main__", "cli", "plotting"}
TOP_PACKAGES = {"plotting"}  # subpackages of the top layer: the figures, by subject
# Only the command line defers imports of the package: cli so that `semitrack --help` and
# bad-input errors answer without importing scipy and the fitting machinery, __main__ so that
# Ctrl-C during those imports is caught; dynamics.simulate so that numba's import (0.3-0.6 s) is paid
# by the runs that use the compiled loop only, not by every import of the time domain.
# The command line defers its heavy imports; simulate and pointfield defer numba (their compiled twins) to first use.
DEFERRED_IMPORTS_ALLOWED = {"semitrack.cli", "semitrack.__main__", "semitrack.dynamics.simulate",
                            "semitrack.fe.pointfield"}


def _modules():
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE).with_suffix("").parts
        yield path, ("semitrack",) + parts


def _layer(parts: tuple[str, ...]) -> int:
    """Layer of the module ``semitrack.<parts...>``."""
    if len(parts) == 1:
        return TOP  # the package root itself
    first = parts[1]
    if first in LAYERS:
        return LAYERS[first]
    if (len(parts) == 2 and first in TOP_MODULES) or first in TOP_PACKAGES:
        return TOP
    raise AssertionError(f"module {'.'.join(parts)} belongs to no layer: add it to LAYERS/TOP_MODULES "
                         "and to ARCHITECTURE.md")


def _imports(path: pathlib.Path, parts: tuple[str, ...]):
    """Yield (imported module parts, line, is_deferred) for every import of semitrack."""
    tree = ast.parse(path.read_text(), filename=str(path))
    package = parts[:-1] if path.name != "__init__.py" else parts[:-1]
    top_level = {id(node) for node in tree.body}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - (node.level - 1)]
                target = base + (tuple(node.module.split(".")) if node.module else ())
            elif node.module and node.module.split(".")[0] == "semitrack":
                target = tuple(node.module.split("."))
            else:
                continue
            yield target, node.lineno, id(node) not in top_level
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "semitrack":
                    yield tuple(alias.name.split(".")), node.lineno, id(node) not in top_level


MODULES = list(_modules())


@pytest.mark.parametrize("path, parts", MODULES, ids=[".".join(p) for _, p in MODULES])
def test_imports_point_down_the_layers(path, parts):
    own = _layer(parts)
    for target, line, _ in _imports(path, parts):
        if len(target) == 1:  # `from semitrack import __version__` / `from . import plotting`
            assert own == TOP, f"{path.name}:{line} imports the package root from layer {own}"
            continue
        theirs = _layer(target)
        assert theirs <= own, (f"{'.'.join(parts)} (layer {own}) imports {'.'.join(target)} "
                               f"(layer {theirs}) at line {line}: imports must point down")


@pytest.mark.parametrize("path, parts", MODULES, ids=[".".join(p) for _, p in MODULES])
def test_no_deferred_imports_of_the_package(path, parts):
    if ".".join(parts) in DEFERRED_IMPORTS_ALLOWED:
        return
    deferred = [line for _, line, is_deferred in _imports(path, parts) if is_deferred]
    assert not deferred, f"{path.name} imports semitrack modules inside functions at lines {deferred}"


def test_architecture_page_names_every_module():
    """ARCHITECTURE.md has one line per module; a new module must be described there."""
    text = (ROOT / "ARCHITECTURE.md").read_text()
    missing = [".".join(p[1:]) for path, p in MODULES
               if path.name != "__init__.py" and f"`{'/'.join(p[1:])}.py`" not in text]
    assert not missing, f"modules missing from ARCHITECTURE.md: {missing}"


def test_layer_table_matches_the_subpackages():
    on_disk = {p.name for p in PACKAGE.iterdir() if p.is_dir() and (p / "__init__.py").exists()} - TOP_PACKAGES
    assert on_disk == set(LAYERS), f"subpackages {sorted(on_disk)} vs layers {sorted(LAYERS)}"


def test_every_lazy_export_resolves_from_a_layer_below_the_top():
    """The flat API is a table (semitrack._EXPORTS); each entry must name a module of a layer
    and an attribute that exists there, and list every name of __all__."""
    assert list(semitrack._EXPORTS) == semitrack.__all__
    for name, (module, attribute) in semitrack._EXPORTS.items():
        assert _layer(("semitrack", *module.split("."))) < TOP, name
        assert getattr(importlib.import_module(f"semitrack.{module}"), attribute) is getattr(semitrack, name)
    with pytest.raises(AttributeError, match="has no attribute 'no_such_name'"):
        semitrack.no_such_name  # noqa: B018


#: The routes of a vehicle's run (interaction/): each imports only the layer's shared part, never another route.
ROUTES = {"fe_model", "window_model", "infinite_convolution", "moving_green"}
SHARED = {"response", "summary", "inputs", "excitation", "convolved_run", "fe_wheels"}
#: The one hand-over between routes: ``wheel_rail_response`` passes a WindowTrack to the window
#: route, the same run on an FE model that travels with the vehicle.
HANDOVER = {"fe_model": {"window_model"}}


def test_the_routes_import_only_the_shared_part_of_their_layer():
    """Each route and ``transfer`` (beside them) imports the shared modules of interaction/ and lower layers only."""
    folder = PACKAGE / "interaction"
    on_disk = {p.stem for p in folder.glob("*.py")} - {"__init__"}
    assert on_disk == ROUTES | SHARED | {"transfer"}, f"interaction/ holds {sorted(on_disk)}: name its part here"
    for path in sorted(folder.glob("*.py")):
        parts = ("semitrack", "interaction", path.stem)
        own = [t[2] for t, _, _ in _imports(path, parts) if t[:2] == ("semitrack", "interaction") and len(t) > 2]
        allowed = (SHARED | HANDOVER.get(path.stem, set()) if path.stem in ROUTES | {"transfer"}
                   else SHARED - {path.stem})
        assert set(own) <= allowed, f"interaction/{path.name} imports {sorted(set(own) - allowed)} of its layer"


@pytest.mark.parametrize("name", sorted(LAYERS))
def test_each_subpackage_names_its_layer(name):
    """The subpackages' docstrings say their layer as the table above and ARCHITECTURE.md number it."""
    doc = ast.get_docstring(ast.parse((PACKAGE / name / "__init__.py").read_text())) or ""
    assert doc.startswith(f"Layer {LAYERS[name]}:"), f"{name}/__init__.py: {doc[:40]!r}"
    assert f"### {name} (layer {LAYERS[name]})" in (ROOT / "ARCHITECTURE.md").read_text()
