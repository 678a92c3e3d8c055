"""Every refusal of an input is the package's own exception, so the command line needs no guessing.

The command line reports :class:`semitrack.base.errors.BadInput` as a refusal (exit 2, one line)
and anything else as an unexpected failure (exit 1, a traceback to report): so no module may
raise a bare ``ValueError`` or ``TypeError``.
"""

import ast
import pathlib

import numpy as np
import pytest

import semitrack as st
from semitrack.base.errors import BadInput, InputError, InputTypeError

PACKAGE = pathlib.Path(st.__file__).parent


@pytest.mark.parametrize("path", sorted(PACKAGE.rglob("*.py")), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_no_bare_value_or_type_error_is_made(path):
    """Neither raised nor built (a helper that returns the error for its caller to raise)."""
    bare = [node.lineno for node in ast.walk(ast.parse(path.read_text()))
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
            and node.func.id in ("ValueError", "TypeError")]
    assert not bare, f"{path.name} makes a bare ValueError/TypeError at lines {bare}: use InputError/InputTypeError"


def test_refusals_are_bad_input_and_still_value_and_type_errors():
    with pytest.raises(InputError, match="kv must be positive and finite") as value:
        st.slab_track(kv=-5e7)
    with pytest.raises(InputTypeError, match="track must be a semitrack.Track") as kind:
        st.semi_infinite_receptance("slab", [100.0])
    assert isinstance(value.value, (BadInput, ValueError)) and isinstance(kind.value, (BadInput, TypeError))
    with pytest.raises(BadInput, match="n_steps = 10000000000 steps"):
        st.FETrack  # noqa: B018 - the flat API stays importable
        from semitrack.fe.timedomain import newmark
        newmark([[1.0]], [[0.0]], [[1.0]], lambda t: np.zeros(1), 1e-9, 10**10)
