"""Uploaded data sets at any fsspec URL (``s3://bucket/prefix``): every worker of every host.

The policy is app/datasets/shared_store.py's, the same as the directory store's, with the
same file names; this module gives it an object store's operations, which lack three
things a directory has:

* **No rename**, but a PUT is atomic per object (S3, GCS, Azure Blob: an object appears
  whole or not at all, and since December 2020 S3 reads and lists are strongly
  consistent after a write), so each file is written with one PUT and a reader sees a
  whole file or none; no temporary objects, none to clean up.
* **No lock across hosts.** ``locked`` orders the writes of one process only. Two hosts
  uploading at the same moment may both see room, so the bound may be exceeded by their
  uploads until the next upload evicts; both may evict the same data set (one reason is
  kept); two uploads of the same new content keep one of their two tokens. No data set
  is ever half-written or lost other than by eviction.
* **A read does not change an object's time.** A use is recorded by PUTting an empty
  ``<name>.used`` object (USE_MARKER) beside it; the listing's time of a file is the
  later of its own and its marker's, both the server's clock (the same for every host).
  S3 counts whole seconds, so uses within one second tie (the LRU then goes by id).

Credentials and the endpoint are the backend's own (for s3fs: ``AWS_ACCESS_KEY_ID``,
``AWS_SECRET_ACCESS_KEY``, ``AWS_ENDPOINT_URL`` for an S3-compatible server, or
fsspec's ``FSSPEC_S3_*`` variables); ``storage_options`` passes them in code.
"""
from __future__ import annotations

import contextlib
import threading
from datetime import datetime

from ..config import INSTALL_S3
from .shared_store import SharedDatasetStore

#: the empty object whose PUT records a use of ``<name>`` (its LastModified is the use)
USE_MARKER = ".used"
#: every call sees the store as it is now: no cached listing (another host writes). The
#: file system object itself may be fsspec's cached one (it then caches nothing of ours)
FRESH = {"use_listings_cache": False}


def _modified(info: dict) -> float:
    """An object's time, in seconds, from whichever key the backend's listing gives."""
    for key in ("LastModified", "mtime", "last_modified", "created"):
        value = info.get(key)
        if isinstance(value, datetime):
            return value.timestamp()
        if isinstance(value, (int, float)):
            return float(value)
    return 0.0


class FsspecFiles:
    """:class:`~app.datasets.shared_store.Files` under an fsspec URL."""

    def __init__(self, url: str, storage_options: dict | None = None):
        try:
            from fsspec.core import url_to_fs
            self.fs, self.root = url_to_fs(url, **FRESH, **(storage_options or {}))
        except ImportError as err:
            raise ImportError(f"the data-set store at {url} needs fsspec and its backend for "
                              f"that scheme ({err}); for s3:// install the extra: {INSTALL_S3}") from err
        self.root = self.root.rstrip("/")
        self._lock = threading.Lock()

    def _path(self, name: str) -> str:
        return f"{self.root}/{name}"

    def list(self) -> dict[str, tuple[int, float]]:
        try:
            infos = self.fs.ls(self.root, detail=True)
        except FileNotFoundError:
            return {}                                   # an empty prefix: nothing stored yet
        files = {info["name"].rsplit("/", 1)[-1]: info for info in infos
                 if info.get("type", "file") == "file"}
        out = {}
        for name, info in files.items():
            if name.endswith(USE_MARKER):
                continue
            used = files.get(name + USE_MARKER)
            last = max(_modified(info), _modified(used) if used else 0.0)
            out[name] = (int(info.get("size") or 0), last)
        return out

    def read(self, name: str) -> bytes:
        return self.fs.cat_file(self._path(name))

    def read_many(self, names: list[str]) -> dict[str, bytes]:
        if not names:
            return {}
        got = self.fs.cat([self._path(n) for n in names], on_error="omit")
        return {path.rsplit("/", 1)[-1]: content for path, content in got.items()}

    def write(self, name: str, content: bytes) -> None:
        self.fs.pipe_file(self._path(name), content)

    def remove(self, name: str) -> None:
        for path in (self._path(name), self._path(name + USE_MARKER)):
            with contextlib.suppress(FileNotFoundError):
                self.fs.rm_file(path)

    def exists(self, name: str) -> bool:
        return self.fs.exists(self._path(name))

    def touch(self, name: str) -> None:
        self.fs.pipe_file(self._path(name + USE_MARKER), b"")

    @contextlib.contextmanager
    def locked(self):
        with self._lock:                                # this process only: see the docstring
            yield

    def clean(self) -> None:
        """Nothing: a PUT leaves no partial object (an abandoned multipart upload, only for
        objects above s3fs's 100 MB, is the bucket's lifecycle rule's to abort)."""


class FsspecDatasetStore(SharedDatasetStore):
    """id → (data set, summary) under ``url``, at most ``max_bytes`` held (but see the
    module's note on concurrent uploads), at most ``client_bytes`` per client."""

    def __init__(self, url: str, max_bytes: int, client_bytes: int | None = None,
                 storage_options: dict | None = None):
        super().__init__(FsspecFiles(url, storage_options), max_bytes, client_bytes)
        self.url = url
