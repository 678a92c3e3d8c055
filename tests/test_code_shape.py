"""Functions short enough to read at once: at most 60 lines of code each in ``src``.

Blank lines, comments and the docstring do not count. A function may be longer only when its
docstring says why, in a sentence that starts with "Long by design:".
"""

from __future__ import annotations

import ast
import io
import pathlib
import tokenize

import semitrack

PACKAGE = pathlib.Path(semitrack.__file__).parent
MAX_CODE_LINES = 60


def _code_lines(source: str) -> set[int]:
    """Line numbers that carry a token other than a comment, newline or string-only statement."""
    lines: set[int] = set()
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type in (tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT, tokenize.DEDENT,
                        tokenize.ENDMARKER):
            continue
        lines.update(range(tok.start[0], tok.end[0] + 1))
    return lines


def _long_functions():
    for path in sorted(PACKAGE.rglob("*.py")):
        source = path.read_text()
        code = _code_lines(source)
        for node in ast.walk(ast.parse(source)):
            if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            doc = ast.get_docstring(node) or ""
            body = node.body
            start = body[0].end_lineno + 1 if doc else body[0].lineno
            n = len([line for line in code if start <= line <= node.end_lineno])
            if n > MAX_CODE_LINES and "Long by design:" not in doc:
                yield f"{path.relative_to(PACKAGE)}:{node.lineno} {node.name} ({n} lines of code)"


def test_functions_are_short():
    long = list(_long_functions())
    assert not long, f"functions over {MAX_CODE_LINES} lines of code without a reason: {long}"
