"""The robustness tests' one check of a refusal: the right error, in one line that names what is wrong, at once."""

import time

import pytest

#: Longest a refusal may take (s), with room for a busy machine (measured: under 0.5 s).
SECONDS = 5.0


def refused(call, cls, *words, seconds: float = SECONDS, cpu: float | None = None) -> str:
    """Call ``call``; it must raise ``cls`` within ``seconds`` with a one-line message holding every word.

    ``cpu`` bounds the CPU time of the process during the call (s): the work done before the refusal,
    whatever else a busy machine runs (issue 34 asks refusals within 1 s).

    Returns
    -------
    str
        The message.
    """
    start, used = time.perf_counter(), time.process_time()
    with pytest.raises(cls) as info:
        call()
    used = time.process_time() - used
    message = str(info.value)
    assert len(message.splitlines()) == 1, message
    for word in words:
        assert word in message, message
    assert time.perf_counter() - start < seconds
    assert cpu is None or used < cpu, f"refused after {used:.2f} s of CPU: {message}"
    return message
