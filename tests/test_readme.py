"""Every snippet of the README runs: each fenced block is extracted and run against a live
server started from this checkout (its URLs pointed at that server's port). Python blocks
run as scripts, bash blocks in a shell (``brdf-explorer`` is this checkout's CLI), a
``text`` block right after a bash block is output that must appear, in order, in what the
block printed (``...`` skips lines), and an iframe's ``src`` must answer 200. The two
commands at the top install things: the second must be what .ci/run runs, the first is
the wheel install that tests/packaging/test_wheel.py performs."""
import os
import re
import stat
import subprocess
import sys
import urllib.request
from pathlib import Path

import pytest

from tests.live import free_port, stop, wait_until_up

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")
BLOCKS = re.findall(r"^```(\w+)\n(.*?)^```$", README, flags=re.S | re.M)
DOCUMENTED = "http://127.0.0.1:8000"
#: Seconds the server may take to start (numba compiles or loads its kernels first) and
#: a block may run (a deck of exports starts Chromium).
START_SECONDS, BLOCK_SECONDS = 240, 600


def test_readme_opens_with_one_sentence_and_the_two_commands():
    title, rest = README.split("\n", 1)
    assert title.startswith("# ")
    first = rest.strip().split("\n\n")[0]
    assert first.count(". ") == 0 and first.endswith(".")            # one sentence
    assert BLOCKS[0] == ("bash", "pip install . && brdf-explorer serve\n")
    ci = (ROOT / ".ci" / "run").read_text().strip().splitlines()[-1]
    assert BLOCKS[1][0] == "bash" and BLOCKS[1][1].strip() == ci
    assert "MATH.md" not in README and not re.search(r"seed \d{3}|\(\d-\d+\)", README)


@pytest.fixture(scope="module")
def server():
    port = free_port()
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen([sys.executable, "-m", "uvicorn", "app.main:app", "--port", str(port)],
                            cwd=ROOT, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    base = f"http://127.0.0.1:{port}"
    try:
        wait_until_up(base + "/api/v1/health", proc, START_SECONDS)
        yield base
    finally:
        stop(proc)


def _shell_env(tmp_path: Path, base: str) -> dict:
    """PATH with ``brdf-explorer`` running this checkout's CLI against the live server."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    shim = bin_dir / "brdf-explorer"
    shim.write_text(f'#!/bin/sh\nexec "{sys.executable}" -m app.cli "$@"\n')
    shim.chmod(shim.stat().st_mode | stat.S_IEXEC)
    return {**os.environ, "PATH": f"{bin_dir}:{os.environ['PATH']}", "PYTHONPATH": str(ROOT)}


def _expect_in_order(expected: str, output: str) -> None:
    lines, at = output.splitlines(), 0
    for want in expected.splitlines():
        if want.strip() in ("", "..."):
            continue
        while at < len(lines) and lines[at].strip() != want.strip():
            at += 1
        assert at < len(lines), f"README output line {want!r} not printed:\n{output}"
        at += 1


RUNNABLE = [(k, lang, body) for k, (lang, body) in enumerate(BLOCKS) if k >= 2 and lang in ("python", "bash", "html")]


@pytest.mark.parametrize("k, lang, body", RUNNABLE, ids=[f"block{k}-{lang}" for k, lang, _ in RUNNABLE])
def test_snippet_runs(k, lang, body, server, tmp_path):
    code = body.replace(DOCUMENTED, server)
    env = _shell_env(tmp_path, server)
    if lang == "html":
        for src in re.findall(r'src="([^"]+)"', code):
            assert urllib.request.urlopen(src, timeout=120).status == 200
        return
    cmd = [sys.executable, "-c", code] if lang == "python" else ["bash", "-euo", "pipefail", "-c", code]
    run = subprocess.run(cmd, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=BLOCK_SECONDS)
    assert run.returncode == 0, f"README block {k} failed:\n{body}\n{run.stdout}\n{run.stderr}"
    following = BLOCKS[k + 1] if k + 1 < len(BLOCKS) else None
    if following is not None and following[0] == "text":
        _expect_in_order(following[1], run.stdout)
