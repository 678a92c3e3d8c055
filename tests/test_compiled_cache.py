"""Every compiled loop is compiled once per machine: a new process reads it from numba's cache.

A run in a child process makes sure the cache holds both loops (the FE model's step loop and the
convolution loop) and the moving kernels' compiled pass; a second child then runs them again and
reports numba's own counts: hits only, no miss (a miss is a compilation: 5-7 s a loop on a 2-core
machine). The convolution loop used to take the compiled contact solve as an argument, which put
a weak reference into numba's cache key: every process missed and saved one more entry, and at
last one failed to read the index.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

pytest.importorskip("numba")

CHILD = r"""
import json, warnings
import semitrack as st
from semitrack.dynamics import compiled
from semitrack.fe import compiled as fe_compiled
warnings.simplefilter("ignore")
track = st.slab_track(damping="viscous")
st.wheel_rail_response(st.TruncatedTrack(track, 2, elements_per_bay=4), st.Wheel(), dt=5e-5, duration=0.03,
                       compiled=True)
st.convolution_response(st.InfiniteTrack(track), st.Wheel(), dt=1e-4, duration=0.03)
st.moving_green_kernels(track, 30.0, 1e-4, memory=0.004, elements_per_bay=4)
kernels = {"_run": compiled._run, "_convolved": compiled._convolved, "_ready": compiled._ready,
           "point_field_into": fe_compiled.point_field_into}
print(json.dumps({name: [sum(k.stats.cache_hits.values()), sum(k.stats.cache_misses.values())]
                  for name, k in kernels.items()}))
"""


def _child() -> dict:
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    out = subprocess.run([sys.executable, "-c", CHILD], capture_output=True, text=True, timeout=600, env=env)
    assert out.returncode == 0, out.stderr[-2000:]
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_a_new_process_reads_every_compiled_loop_from_the_cache():
    _child()  # compiles what the cache does not hold yet
    counts = _child()
    for name, (hits, misses) in counts.items():
        assert misses == 0 and hits >= 1, (name, hits, misses)
