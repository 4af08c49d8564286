"""Uploaded data sets in a directory shared by every worker of one host, surviving restarts.

The store's policy (content addressing, the byte bound, LRU eviction with 410 and the
reason, the per-client quota, delete tokens) is app/datasets/shared_store.py's; this
module gives it a directory's files. Every file is written to a ``*.<pid>.tmp`` name and
renamed into place (``os.replace`` is atomic on one file system), so a reader sees a
whole file or none; ``*.tmp`` files left by a process that died (a crash, a full disk)
are removed when a store opens the directory and before each write. An ``flock`` on
``.lock`` orders the writes of every process of the host, so the bound is never exceeded.
A read touches the ``.npz`` file's mtime: the LRU's "last used".
"""
from __future__ import annotations

import contextlib
import fcntl
import os
from pathlib import Path

from .shared_store import SharedDatasetStore

#: the file every writer locks (not a data set's)
LOCK = ".lock"
#: the suffix of a file being written (``<name>.<pid>.tmp``), renamed when whole
TMP = ".tmp"


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


class DirectoryFiles:
    """:class:`~app.datasets.shared_store.Files` in a directory."""

    def __init__(self, root: str | os.PathLike):
        self.root = Path(root)
        self.root.mkdir(parents=True, exist_ok=True)
        self.clean()

    def list(self) -> dict[str, tuple[int, float]]:
        out = {}
        with os.scandir(self.root) as entries:
            for entry in entries:
                if entry.name == LOCK or entry.name.endswith(TMP):
                    continue
                try:
                    stat = entry.stat()
                except OSError:
                    continue                                   # removed since the scan
                out[entry.name] = (stat.st_size, stat.st_mtime)
        return out

    def read(self, name: str) -> bytes:
        return (self.root / name).read_bytes()

    def read_many(self, names: list[str]) -> dict[str, bytes]:
        out = {}
        for name in names:
            with contextlib.suppress(OSError):
                out[name] = self.read(name)
        return out

    def write(self, name: str, content: bytes) -> None:
        path = self.root / name
        tmp = path.with_name(f"{name}.{os.getpid()}{TMP}")
        try:
            with open(tmp, "wb") as fh:
                fh.write(content)
            os.replace(tmp, path)
        except OSError:
            tmp.unlink(missing_ok=True)
            raise

    def remove(self, name: str) -> None:
        (self.root / name).unlink(missing_ok=True)

    def exists(self, name: str) -> bool:
        return (self.root / name).exists()

    def touch(self, name: str) -> None:
        with contextlib.suppress(FileNotFoundError):     # evicted meanwhile: nothing to record
            os.utime(self.root / name)

    @contextlib.contextmanager
    def locked(self):
        with open(self.root / LOCK, "a+") as fh:
            fcntl.flock(fh, fcntl.LOCK_EX)
            try:
                yield
            finally:
                fcntl.flock(fh, fcntl.LOCK_UN)

    def clean(self) -> None:
        """Remove ``*.tmp`` files whose writing process is gone (crash, disk full)."""
        for tmp in self.root.glob(f"*{TMP}"):
            try:
                pid = int(tmp.name.rsplit(".", 2)[-2])
            except (ValueError, IndexError):
                pid = -1
            if pid != os.getpid() and (pid < 0 or not _pid_alive(pid)):
                tmp.unlink(missing_ok=True)


class DiskDatasetStore(SharedDatasetStore):
    """id → (data set, summary) in the directory ``root``, at most ``max_bytes`` on disk,
    at most ``client_bytes`` per client."""

    def __init__(self, root: str | os.PathLike, max_bytes: int, client_bytes: int | None = None):
        super().__init__(DirectoryFiles(root), max_bytes, client_bytes)
        self.root = self.files.root
