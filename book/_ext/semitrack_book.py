"""Sphinx extension of the semitrack book: what the stock Jupyter Book 1.x setup lacks.

- ``{api-reference}`` on a page (see ``book/api.md``) becomes the API reference: one autodoc entry
  per name of ``semitrack.__all__``, grouped by the layer that defines it, so the page can never
  miss a public name.
- Bibliography labels honour a ``shorthand`` field (as biblatex does): the reproduced paper names
  no author or year, and pybtex's alpha labels would otherwise spell "Therpaperd."-like labels.
- sphinx-thebe registers its inline configuration script twice under Jupyter Book 1.0, which
  declares ``const THEBE_JS_URL`` twice and throws a SyntaxError in every page: keep one copy.
"""

from __future__ import annotations

import importlib

from pybtex.plugin import register_plugin
from pybtex.style.formatting.alpha import Style as AlphaStyle
from pybtex.style.labels.alpha import LabelStyle as AlphaLabelStyle
from sphinx.pycode import ModuleAnalyzer

API_PLACEHOLDER = "{api-reference}"
PACKAGE = "semitrack"


# ----------------------------------------------------------------------------- bibliography
class ShorthandLabelStyle(AlphaLabelStyle):
    """Alpha labels (Mea96), except that an entry's ``shorthand`` field is used as it is."""

    def format_labels(self, sorted_entries):
        alpha = super().format_labels(sorted_entries)
        for entry, label in zip(sorted_entries, alpha, strict=True):
            yield entry.fields.get("shorthand", label)


class ShorthandStyle(AlphaStyle):
    """pybtex's alpha style with :class:`ShorthandLabelStyle` labels."""

    default_label_style = ShorthandLabelStyle


# ----------------------------------------------------------------------------- API reference
def public_names(package: str = PACKAGE) -> dict[str, tuple[str, str]]:
    """Map every name of ``package.__all__`` to (defining module, name there).

    Read from the package's lazy-export table ``_EXPORTS`` (``{name: (module, attribute)}``).
    """
    module = importlib.import_module(package)
    exports = getattr(module, "_EXPORTS", {})
    missing = sorted(set(module.__all__) - set(exports))
    if missing:
        raise RuntimeError(f"{package}.__all__ names missing from {package}._EXPORTS: {missing}")
    return {name: (f"{package}.{exports[name][0]}", exports[name][1]) for name in module.__all__}


def _entry(name: str, module_name: str, source_name: str) -> str:
    """The reStructuredText of one public name: autodoc for code, the ``#:`` comment for data."""
    obj = getattr(importlib.import_module(PACKAGE), name)
    qualified = f"{PACKAGE}.{name}"
    if isinstance(obj, type):
        return f".. autoclass:: {qualified}\n   :members:\n"
    if callable(obj):
        return f".. autofunction:: {qualified}\n"
    docs = ModuleAnalyzer.for_module(module_name).find_attr_docs().get(("", source_name), [])
    body = "".join(f"   {line}\n" for line in docs if line) or "   (undocumented)\n"
    return f".. py:data:: {qualified}\n\n{body}"


def api_reference_markdown(package: str = PACKAGE) -> str:
    """MyST text of the API reference: a section per layer, an autodoc entry per public name."""
    groups: dict[str, list[str]] = {}
    for name, (module_name, source_name) in public_names(package).items():
        layer = ".".join(module_name.split(".")[:2])
        groups.setdefault(layer, []).append(_entry(name, module_name, source_name))
    parts = []
    for layer in sorted(groups, key=lambda m: importlib.import_module(m).__doc__.split(":")[0]):
        summary = importlib.import_module(layer).__doc__.strip().splitlines()[0]
        title = summary.split(":", 1)[1].strip().rstrip(".")
        parts.append(f"## {title[0].upper()}{title[1:]}\n\nDefined in `{layer}`.\n\n"
                     "```{eval-rst}\n" + "\n".join(groups[layer]) + "```\n")
    return "\n".join(parts)


def _insert_api_reference(app, docname: str, source: list[str]) -> None:
    if API_PLACEHOLDER in source[0]:
        source[0] = source[0].replace(API_PLACEHOLDER, api_reference_markdown())


# ----------------------------------------------------------------------------- scripts
def _drop_duplicate_scripts(app, pagename, templatename, context, doctree) -> None:
    scripts = context.get("script_files")
    if not scripts:
        return
    seen, unique = set(), []
    for script in scripts:
        # The copies differ only in filename (None or ''): an inline script is its body.
        key = getattr(script, "attributes", {}).get("body") or getattr(script, "filename", script)
        if key not in seen:
            seen.add(key)
            unique.append(script)
    context["script_files"] = unique


def setup(app):
    register_plugin("pybtex.style.formatting", "semitrack", ShorthandStyle)
    app.connect("source-read", _insert_api_reference)
    app.connect("html-page-context", _drop_duplicate_scripts, priority=900)  # after the others add theirs
    return {"parallel_read_safe": True, "parallel_write_safe": True}
