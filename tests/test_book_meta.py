"""The book's furniture: licence, citation file, API reference, bibliography labels, offline math."""

import importlib.util
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
import yaml

import semitrack as st

ROOT = Path(__file__).resolve().parents[1]


def _load(path: Path, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def book_ext():
    return _load(ROOT / "book" / "_ext" / "semitrack_book.py", "semitrack_book")


def _pyproject() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]


def test_license_is_the_mit_text_pyproject_declares():
    text = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert _pyproject()["license"] == "MIT"
    assert text.startswith("MIT License")
    assert "Permission is hereby granted, free of charge" in text


def test_citation_file_parses_and_matches_the_package():
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text(encoding="utf-8"))
    # The keys the CFF 1.2.0 schema requires (full validation: cffconvert in .ci/run).
    assert cff["cff-version"] == "1.2.0"
    assert cff["message"].strip() and cff["title"].strip()
    assert cff["authors"] and all("name" in a or "family-names" in a for a in cff["authors"])
    assert cff["version"] == _pyproject()["version"] == st.__version__
    assert cff["license"] == _pyproject()["license"]


def test_api_reference_documents_every_public_name(book_ext):
    text = book_ext.api_reference_markdown()
    directives = ("autofunction", "autoclass", "py:data")
    for name in st.__all__:
        assert any(f".. {d}:: semitrack.{name}\n" in text for d in directives), name
    assert "(undocumented)" not in text  # every public data name has a #: comment
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text(encoding="utf-8"))
    files = [c["file"] for part in toc["parts"] for c in part["chapters"]]
    assert "book/api" in files
    assert book_ext.API_PLACEHOLDER in (ROOT / "book" / "api.md").read_text(encoding="utf-8")


def test_api_reference_refuses_a_public_name_it_cannot_trace(book_ext, tmp_path, monkeypatch):
    package = tmp_path / "fakepkg"
    package.mkdir()
    (package / "core.py").write_text("def f():\n    pass\n")
    (package / "__init__.py").write_text("_EXPORTS = {'f': ('core', 'f')}\n__all__ = ['f', 'g']\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    with pytest.raises(RuntimeError, match=r"\['g'\]"):
        book_ext.public_names("fakepkg")


def test_bibliography_labels_use_the_shorthand(book_ext):
    from pybtex.database import parse_file

    entries = parse_file(str(ROOT / "book" / "references.bib")).entries
    paper = entries["receptance_paper"]
    # Our copy of the paper names no authors and no year: the entry must not invent them.
    assert not paper.persons and "year" not in paper.fields
    assert paper.fields["title"].startswith("Receptance of a semi-infinite periodic railway track")
    keys = ["receptance_paper", "mead1996"]
    labels = list(book_ext.ShorthandLabelStyle().format_labels([entries[k] for k in keys]))
    assert labels == ["Paper", "Mea96"]


def _page(folder: Path, script: str, math: bool = True) -> None:
    body = '<span class="math notranslate">\\(x\\)</span>' if math else "<p>text</p>"
    (folder / "page.html").write_text(f"<html><head>{script}</head><body>{body}</body></html>")


@pytest.mark.parametrize(("script", "ok"), [
    ('<script defer src="_static/mathjax/tex-chtml.js"></script>', True),
    ('<script defer src="https://cdn.jsdelivr.net/npm/mathjax@3/es5/tex-mml-chtml.js"></script>', False),
    ('<script defer src="_static/mathjax/missing.js"></script>', False),
    ("", False),
])
def test_offline_math_check(tmp_path, script, ok):
    (tmp_path / "_static" / "mathjax").mkdir(parents=True)
    (tmp_path / "_static" / "mathjax" / "tex-chtml.js").write_text("// MathJax")
    _page(tmp_path, script)
    run = subprocess.run([sys.executable, str(ROOT / ".ci" / "check_offline_book.py"), str(tmp_path)],
                         capture_output=True, text=True, check=False)
    assert (run.returncode == 0) == ok, run.stdout + run.stderr


def test_code_cells_fold_by_one_rule():
    """Every code cell of a chapter is folded (``hide-input``: its output shows, the code behind a
    click), except the how-to's, whose commands are what it teaches; citations show their labels."""
    import json

    for path in sorted((ROOT / "book").glob("*.ipynb")):
        cells = json.loads(path.read_text(encoding="utf-8"))["cells"]
        shown = [i for i, c in enumerate(cells) if c["cell_type"] == "code"
                 and "hide-input" not in c.get("metadata", {}).get("tags", [])]
        assert (shown == []) != (path.name == "howto.ipynb"), f"{path.name}: code cells {shown} not folded"
    config = yaml.safe_load((ROOT / "_config.yml").read_text(encoding="utf-8"))
    assert config["sphinx"]["config"]["bibtex_reference_style"] == "label"  # the paper has no author or year
