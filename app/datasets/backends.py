"""The data-set store a location names: a directory (or ``file://`` URL) is the directory
store, every worker of one host; any other fsspec URL (``s3://bucket/prefix``) the fsspec
store, every worker of every host. Both keep the same policy (shared_store.py)."""
from __future__ import annotations

import os

from ..config import remote_scheme
from .disk_store import DiskDatasetStore
from .shared_store import SharedDatasetStore

FILE_URL = "file://"


def open_store(location: str | os.PathLike, max_bytes: int,
               client_bytes: int | None = None) -> SharedDatasetStore:
    """The store at ``location``; OSError where a directory cannot be made, ImportError
    (naming the extra to install) where a URL's backend is missing."""
    location = str(location)
    if remote_scheme(location):
        from .fsspec_store import FsspecDatasetStore    # fsspec only where a URL asks for it
        return FsspecDatasetStore(location, max_bytes, client_bytes)
    if location.startswith(FILE_URL):
        location = location[len(FILE_URL):]
    return DiskDatasetStore(location, max_bytes, client_bytes)
