"""The time-domain engine reproduces the results of the engine it replaced, to 1e-10.

``tests/data/timedomain_reference.npz`` holds the outputs of every run of
``tests/timedomain_cases.py`` as the old engine (``newmark`` with its load, output and
correction hooks, commit 93d90fd) computed them. Each channel is compared on the scale of its
motion, ``max |x - x_ref(0)|``, not of its static offset: the contact force's fluctuation is a
few percent of the preload, and a tolerance on the preload would hide errors 30 times larger.
The tolerance 1e-10 leaves room for the round-off of a different factorisation (banded
Cholesky instead of a pivoted band LU), measured at 1e-13-1e-12.
"""

import numpy as np
import pytest
from timedomain_cases import REFERENCE, cases, key

CASES = cases()


@pytest.fixture(scope="module")
def reference():
    with np.load(REFERENCE) as z:
        return {k: z[k] for k in z.files}


@pytest.mark.parametrize("case", CASES)
def test_the_engine_reproduces_its_predecessor(reference, case):
    for channel, value in CASES[case]().items():
        ref = reference[key(case, channel)]
        assert value.shape == ref.shape, channel
        error = np.max(np.abs(value - ref))
        assert error <= 1e-10 * np.max(np.abs(ref)), (channel, error / np.max(np.abs(ref)))
        if channel == "force":
            motion = np.max(np.abs(ref - ref[0]))
            assert error <= 1e-9 * motion, error / motion
