"""Every snippet of the README (and of the docs it sends a reader to for the details) runs:
each fenced block is extracted and run against a live server started from this checkout
(its URLs pointed at that server's port). Python blocks run as scripts, bash blocks in a
shell (``brdf-explorer`` is this checkout's CLI), a ``text`` block right after a bash
block is output that must appear, in order, in what the block printed (``...`` skips
lines), and an iframe's ``src`` must answer 200. Two commands install things and are
not run: the first block (the wheel install tests/packaging/test_wheel.py performs) and
the one under "Development", which must be what .ci/run runs."""
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
#: the docs whose examples the README leaves out and links to instead
DETAIL_DOCS = ("docs/accuracy.md", "docs/teaching.md")
FENCE = re.compile(r"^```(\w+)\n(.*?)^```$", flags=re.S | re.M)
BLOCKS = FENCE.findall(README)
DOCUMENTED = "http://127.0.0.1:8000"
CI = (ROOT / ".ci" / "run").read_text().strip().splitlines()[-1]
INSTALL = "pip install . && brdf-explorer serve\n"
#: Seconds the server may take to start (numba compiles or loads its kernels first) and
#: a block may run (a deck of exports starts Chromium).
START_SECONDS, BLOCK_SECONDS = 240, 600
#: the API's parts the README must show (issue 34: the newer half was out of sight)
API_PARTS = ("/datasets", "/fit", "/code", "/lut", "/conventions", "/materials", "/principled",
             "sphere_env", "/batch", "/eval", "/albedo", "/figures/", "/embed/")
#: what a user wants to do, each with a heading of its own
TASKS = ("See a BRDF", "Compare models", "Bring your data", "Take the code", "Teach with it")


def _section(heading: str) -> str:
    found = re.search(rf"^## {re.escape(heading)}\n(.*?)(?=^## |\Z)", README, flags=re.S | re.M)
    assert found, f"README has no '## {heading}' section"
    return found.group(1)


def test_readme_opens_with_one_sentence_and_the_start_command():
    title, rest = README.split("\n", 1)
    assert title.startswith("# ")
    first = rest.strip().split("\n\n")[0]
    assert first.count(". ") == 0 and first.endswith(".")            # one sentence
    assert BLOCKS[0] == ("bash", INSTALL)
    assert "127.0.0.1:8000" in rest.strip().split("\n\n")[2]          # where it starts, said next
    assert "MATH.md" not in README and not re.search(r"seed \d{3}|\(\d-\d+\)", README)


def test_the_test_command_is_ci_s_under_development():
    development = FENCE.findall(_section("Development"))
    assert ("bash", CI + "\n") in development
    assert CI not in README.split("## ", 1)[0]                         # not beside the start command


def test_readme_is_organised_by_task_and_shows_the_whole_api():
    for task in TASKS:
        assert FENCE.search(_section(task)), f"'{task}' has no example"
        assert re.search(r"\]\((docs/[\w-]+\.md)\)", _section(task)), f"'{task}' links no doc"
    for part in API_PARTS:
        assert part in README, part
    for doc in ("docs/datasets.md", "docs/shaders.md", "docs/principled.md"):
        assert f"]({doc})" in README
    assert len(README.splitlines()) < 362                             # shorter than it was


@pytest.mark.parametrize("path", ["README.md", *DETAIL_DOCS])
def test_relative_links_lead_to_files(path):
    text = (ROOT / path).read_text(encoding="utf-8")
    for target in re.findall(r"\]\(([^)#:]+)(?:#[^)]*)?\)", text):
        assert (ROOT / path).parent.joinpath(target).resolve().exists(), f"{path}: {target}"


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


def _runnable(path: str):
    blocks = FENCE.findall((ROOT / path).read_text(encoding="utf-8"))
    for k, (lang, body) in enumerate(blocks):
        if lang in ("python", "bash", "html") and body not in (INSTALL, CI + "\n"):
            following = blocks[k + 1] if k + 1 < len(blocks) else None
            yield pytest.param(lang, body, following if following and following[0] == "text" else None,
                               id=f"{path}-block{k}-{lang}")


RUNNABLE = [p for path in ("README.md", *DETAIL_DOCS) for p in _runnable(path)]


@pytest.mark.parametrize("lang, body, expected", RUNNABLE)
def test_snippet_runs(lang, body, expected, server, tmp_path):
    code = body.replace(DOCUMENTED, server)
    env = _shell_env(tmp_path, server)
    if lang == "html":
        for src in re.findall(r'src="([^"]+)"', code):
            assert urllib.request.urlopen(src, timeout=120).status == 200
        return
    cmd = [sys.executable, "-c", code] if lang == "python" else ["bash", "-euo", "pipefail", "-c", code]
    run = subprocess.run(cmd, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=BLOCK_SECONDS)
    assert run.returncode == 0, f"block failed:\n{body}\n{run.stdout}\n{run.stderr}"
    if expected is not None:
        _expect_in_order(expected[1], run.stdout)
