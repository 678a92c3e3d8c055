"""Every command of README.md runs as typed, as a newcomer would run it.

After the set-up block at the top (which makes ``.venv``) the README activates the environment;
here activation is PATH starting with the folder of this Python, so that ``semitrack`` and
``python`` are this environment's. Every other ``bash`` block runs line by line, in README
order, and every ``python`` block as a script, each in a fresh folder; each must exit 0.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"
ACTIVATE = "source .venv/bin/activate"
FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.MULTILINE | re.DOTALL)


def blocks(text: str) -> list[tuple[str, str]]:
    """(language, body) of each fenced block, in order."""
    return FENCE.findall(text)


def setup_lines(text: str) -> list[str]:
    """The lines of the first block: the set-up (a fresh venv, then the book or the tests)."""
    return [line.strip() for line in blocks(text)[0][1].splitlines() if line.strip()]


def shell_commands(text: str) -> list[str]:
    """The command lines of every bash block but the set-up one: no comments, set-up or activation."""
    skip = {*setup_lines(text), ACTIVATE}
    lines = (line.strip() for lang, body in blocks(text)[1:] if lang == "bash" for line in body.splitlines())
    return [line for line in lines if line and not line.startswith("#") and line not in skip]


def python_scripts(text: str) -> list[str]:
    return [body for lang, body in blocks(text) if lang == "python"]


def activated_env() -> dict[str, str]:
    """The environment after ``source .venv/bin/activate``: this Python's folder first on PATH."""
    env = dict(os.environ)
    env["PATH"] = os.path.dirname(sys.executable) + os.pathsep + env.get("PATH", "")
    env.setdefault("OPENBLAS_NUM_THREADS", "1")
    return env


def start(args: list[str], cwd: Path) -> subprocess.Popen:
    cwd.mkdir(exist_ok=True)
    return subprocess.Popen(args, cwd=cwd, env=activated_env(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            text=True)


def check_exit(process: subprocess.Popen, what: str) -> None:
    _, stderr = process.communicate(timeout=600)
    assert process.returncode == 0, f"README {what} exited {process.returncode}:\n{stderr[-3000:]}"


#: Run before each python block: the README uses only the names of the package's naming rule.
OWN_NAMES_ONLY = (
    "import warnings\n"
    "warnings.filterwarnings('error', message='.*the package.s naming rule', category=DeprecationWarning)\n"
    "warnings.filterwarnings('error', message='.*x is measured from a mid-span since', category=FutureWarning)\n")


def test_set_up_then_activation_then_examples():
    """The two set-up lines stay first; activation comes before any example that needs it."""
    text = README.read_text()
    assert blocks(text)[0][0] == "bash"
    assert [line.split("&&")[:2] for line in setup_lines(text)] == [
        ["python3 -m venv .venv ", " .venv/bin/pip install -r requirements.txt "]] * 2
    first_use = min(text.index("```python"), text.index("\nsemitrack "))
    assert 0 < text.find(ACTIVATE) < first_use
    assert shell_commands(text)[:2] == ["semitrack example slab > slab.toml",
                                        "semitrack example ballasted > ballasted.toml"]


def test_readme_runs_as_typed(tmp_path):
    """Each python block as a script and, beside it (the fits are single-threaded), each shell line."""
    text = README.read_text()
    commands, scripts = shell_commands(text), python_scripts(text)
    assert len(commands) >= 5 and scripts
    for n, code in enumerate(scripts, start=1):  # each an error on an old name or a left-out origin
        (tmp_path / f"readme_{n}.py").write_text(OWN_NAMES_ONLY + code)
    pythons = [start([sys.executable, str(tmp_path / f"readme_{n}.py")], tmp_path / "python")
               for n in range(1, len(scripts) + 1)]
    try:
        for command in commands:  # in README order: later lines read the files earlier lines write
            check_exit(start(["bash", "-c", command], tmp_path / "shell"), repr(command))
        for n, process in enumerate(pythons, start=1):
            check_exit(process, f"python block {n}")
    finally:
        for process in pythons:
            process.kill()
            process.communicate()
