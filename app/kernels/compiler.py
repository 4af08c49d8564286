"""A separate process that compiles generated kernel modules into numba's disk cache.

numba compiles in Python, holding the GIL for seconds: in the server's process that
would halve every request's share of the interpreter while the loops compile. So the
server's background thread hands each module part that is not in the cache yet to
this process (at a lower CPU priority), one ``<part> <path>`` per line on its stdin
(kernel.PARTS; ``all`` for every loop), and loads the result from the cache when it
answers ``ok <part> <path>`` (or ``failed <part> <path> <reason>``).

    python -c "from app.kernels.compiler import main; main()"   (lines on stdin until EOF)
"""
from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
import threading
from pathlib import Path

#: nice value of the compiling process: requests first
NICE = 10


def compile_module(path: Path, part: str | None = None) -> None:
    """Import a generated module and compile (or load) the loops of ``part`` (every loop
    when None)."""
    from .compose import FLOAT32_PREFIX, compiling
    from .kernel32 import Kernel32
    from .kernel import Kernel
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[path.stem] = module
    spec.loader.exec_module(module)
    with compiling(module):
        if path.stem.startswith(FLOAT32_PREFIX):      # the float32 f loop: its own argument types
            Kernel32(None, module).warm()
        else:
            Kernel(None, module).warm(part)


def main() -> int:
    try:
        os.nice(NICE)
    except OSError:
        pass
    for line in sys.stdin:
        part, path = line.strip().split(" ", 1)
        try:
            compile_module(Path(path), None if part == "all" else part)
            answer = f"ok {part} {path}"
        except Exception as exc:   # reported to the server, which then serves numpy
            answer = f"failed {part} {path} {type(exc).__name__}: {exc}".replace("\n", " ")
        try:
            print(answer, flush=True)
        except BrokenPipeError:    # the server has gone: so do we
            return 0
    return 0


class Client:
    """The server's handle on one compiler process, started on first use."""

    def __init__(self):
        self._proc: subprocess.Popen | None = None
        self._lock = threading.Lock()

    def compile(self, path: Path, part: str | None = None) -> str | None:
        """None when the loops of ``part`` (every loop: None) are compiled, else the
        reason they were not."""
        request = f"{part or 'all'} {path}"
        with self._lock:
            if self._proc is None or self._proc.poll() is not None:
                env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in sys.path if p)}
                self._proc = subprocess.Popen(
                    [sys.executable, "-c", "from app.kernels.compiler import main; main()"],
                    stdin=subprocess.PIPE,
                    stdout=subprocess.PIPE, text=True, env=env, bufsize=1)
            try:
                self._proc.stdin.write(f"{request}\n")
                self._proc.stdin.flush()
                answer = self._proc.stdout.readline().strip()
            except (BrokenPipeError, OSError) as exc:
                return f"compiler process: {exc}"
        if answer == f"ok {request}":
            return None
        return answer or "compiler process ended"


#: The one compiler process of this server process (started on first use), shared by the
#: float64 loops (kernels/__init__.py) and the float32 loop (float32.py)
CLIENT = Client()
