"""The robustness tests' one check of a refusal: the right error, in one line that names what is wrong, at once."""

import time

import pytest

#: Longest a refusal may take (s), with room for a busy machine (measured: under 0.5 s).
SECONDS = 5.0


def refused(call, cls, *words, seconds: float = SECONDS) -> str:
    """Call ``call``; it must raise ``cls`` within ``seconds`` with a one-line message holding every word.

    Returns
    -------
    str
        The message.
    """
    start = time.perf_counter()
    with pytest.raises(cls) as info:
        call()
    message = str(info.value)
    assert len(message.splitlines()) == 1, message
    for word in words:
        assert word in message, message
    assert time.perf_counter() - start < seconds
    return message
