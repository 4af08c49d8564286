"""Uploaded data sets in a directory shared by every worker, surviving restarts.

Content-addressed: ``<id>.npz`` holds the data set's arrays, ``<id>.json`` its format,
summary, owner and the hashes of its delete tokens. Every file is written to a
``*.<pid>.tmp`` name and renamed into place (``os.replace`` is atomic on one file
system), so a reader sees a whole file or none; ``*.tmp`` files left by a process that
died (a crash, a full disk) are removed when a store opens the directory and before
each write. A process-wide ``flock`` on ``.lock`` orders writes between workers.

Bounded in bytes (``max_bytes``): the least recently used data set (file mtime, touched
by every read) is evicted first, leaving ``<id>.gone`` with the reason, so a later GET
answers 410 "expired (why)" instead of 404. A per-client quota (``client_bytes``): an
upload first evicts its own client's oldest data sets beyond the quota, so one client
alone holds at most ``client_bytes`` and cannot push out more than that of anyone else's.
Deleting needs a token the upload answered (a secret, stored only as its hash), not the
id alone: the id is a hash of public content.

The interface (``put``, ``get``, ``delete``, ``in``) is the in-memory store's, plus the
client and token; another backend (an fsspec URL such as ``s3://bucket/prefix``) would
implement the same five methods over ``fsspec.open`` with the same file names.
"""
from __future__ import annotations

import contextlib
import fcntl
import io
import json
import os
import secrets
from pathlib import Path

import numpy as np

from .. import npz
from ..errors import TooLarge
from .dataset import BrdfData, TermData
from .store import Expired, Forbidden, Unknown, token_hash as _hash, token_matches




def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _encode(data) -> tuple[dict, dict]:
    """(meta, arrays) of a data set, to rebuild it exactly."""
    if isinstance(data, TermData):
        return ({"class": "term", "format": data.format, "axis": data.axis, "size": data.size,
                 "terms": list(data.terms)},
                {"x": data.x, **{f"term_{k}": v for k, v in data.terms.items()}})
    arrays = {k: getattr(data, k) for k in ("table", "l", "v", "f") if getattr(data, k) is not None}
    return {"class": "brdf", "format": data.format, "channels": list(data.channels),
            "size": data.size}, arrays


def _decode(meta: dict, arrays) -> object:
    if meta["class"] == "term":
        return TermData(meta["format"], meta["axis"], arrays["x"],
                        {k: arrays[f"term_{k}"] for k in meta["terms"]}, meta["size"])
    return BrdfData(meta["format"], tuple(meta["channels"]), meta["size"],
                    **{k: arrays[k] for k in ("table", "l", "v", "f") if k in arrays})


class DiskDatasetStore:
    """id → (data set, summary) in ``root``, at most ``max_bytes`` on disk, at most
    ``client_bytes`` per client."""

    def __init__(self, root: str | os.PathLike, max_bytes: int, client_bytes: int | None = None):
        self.root = Path(root)
        self.root.mkdir(parents=True, exist_ok=True)
        self.max_bytes = max_bytes
        self.client_bytes = client_bytes or max_bytes
        self._clean_tmp()

    # -- files ------------------------------------------------------------------------
    def _path(self, data_id: str, suffix: str) -> Path:
        return self.root / f"{data_id}{suffix}"

    @contextlib.contextmanager
    def _locked(self):
        with open(self.root / ".lock", "a+") as fh:
            fcntl.flock(fh, fcntl.LOCK_EX)
            try:
                yield
            finally:
                fcntl.flock(fh, fcntl.LOCK_UN)

    def _write(self, path: Path, content: bytes) -> None:
        tmp = path.with_name(f"{path.name}.{os.getpid()}.tmp")
        try:
            with open(tmp, "wb") as fh:
                fh.write(content)
            os.replace(tmp, path)
        except OSError:
            tmp.unlink(missing_ok=True)
            raise

    def _clean_tmp(self) -> None:
        """Remove ``*.tmp`` files whose writing process is gone (crash, disk full)."""
        for tmp in self.root.glob("*.tmp"):
            try:
                pid = int(tmp.name.rsplit(".", 2)[-2])
            except (ValueError, IndexError):
                pid = -1
            if pid != os.getpid() and (pid < 0 or not _pid_alive(pid)):
                tmp.unlink(missing_ok=True)

    def _entries(self) -> list[tuple[float, str, int, str]]:
        """(last use, id, bytes, client) of every stored data set."""
        out = []
        for meta_path in self.root.glob("*.json"):
            data_id = meta_path.stem
            npz = self._path(data_id, ".npz")
            try:
                meta = json.loads(meta_path.read_text())
                out.append((npz.stat().st_mtime, data_id, npz.stat().st_size, meta.get("client", "")))
            except (OSError, ValueError):
                continue
        return sorted(out)

    def _evict(self, data_id: str, why: str) -> None:
        self._write(self._path(data_id, ".gone"), why.encode())
        for suffix in (".npz", ".json"):
            self._path(data_id, suffix).unlink(missing_ok=True)

    # -- the store's interface ----------------------------------------------------------
    def __contains__(self, data_id: str) -> bool:
        return self._path(data_id, ".json").exists() and self._path(data_id, ".npz").exists()

    def put(self, data_id: str, data, summary: dict, client: str = "") -> str:
        """Store the data set (once per content) and answer a new delete token for it."""
        meta, arrays = _encode(data)
        buffer = io.BytesIO()
        np.savez(buffer, **arrays)
        content = buffer.getvalue()
        limit = min(self.max_bytes, self.client_bytes)
        if len(content) > limit:
            raise TooLarge("file", f"this data set needs {len(content)} bytes stored; a client may "
                                   f"hold {limit} (settings BRDF_MAX_DATASETS_BYTES and the "
                                   "per-client quota)", loc="body")
        token = secrets.token_urlsafe(16)
        with self._locked():
            self._clean_tmp()
            old = self._read_meta(data_id)
            if old is not None:      # the same content again: one more owner's token
                old["tokens"].append(_hash(token))
                self._write(self._path(data_id, ".json"), json.dumps(old).encode())
                os.utime(self._path(data_id, ".npz"))
                return token
            entries = self._entries()
            own = sum(size for _, _, size, who in entries if who == client)
            for _, old_id, size, who in entries:            # the client's own, oldest first
                if who == client and own + len(content) > self.client_bytes:
                    self._evict(old_id, f"evicted, the oldest of its client's data sets, to keep "
                                        f"that client within its quota of {self.client_bytes} bytes")
                    own -= size
            entries = self._entries()
            total = sum(size for _, _, size, _ in entries)
            for _, old_id, size, _ in entries:              # then anyone's, least recently used
                if total + len(content) <= self.max_bytes:
                    break
                self._evict(old_id, f"evicted, least recently used, to keep the store within "
                                    f"BRDF_MAX_DATASETS_BYTES={self.max_bytes}")
                total -= size
            self._write(self._path(data_id, ".npz"), content)
            self._write(self._path(data_id, ".json"), json.dumps(
                {**meta, "summary": summary, "client": client, "tokens": [_hash(token)]}).encode())
            self._path(data_id, ".gone").unlink(missing_ok=True)
        return token

    def _read_meta(self, data_id: str) -> dict | None:
        try:
            return json.loads(self._path(data_id, ".json").read_text())
        except (OSError, ValueError):
            return None

    def get(self, data_id: str, param: str = "data", loc: str = "body") -> tuple:
        """(data set, summary); 410 with the reason for an evicted or deleted id, 404 for an
        unknown one."""
        meta = self._read_meta(data_id)
        if meta is not None:
            try:
                data = _decode(meta, npz.read(self._path(data_id, ".npz")))
                os.utime(self._path(data_id, ".npz"))        # the LRU's "last used"
                return data, meta["summary"]
            except (OSError, ValueError, KeyError):
                pass                                          # evicted between the two reads
        try:
            why = self._path(data_id, ".gone").read_text()
        except OSError:
            raise Unknown(data_id, param, loc) from None
        raise Expired(data_id, why, param, loc)

    def delete(self, data_id: str, token: str | None = None, param: str = "data_id",
               loc: str = "path") -> None:
        with self._locked():
            meta = self._read_meta(data_id)
            if meta is None:
                self.get(data_id, param, loc)                 # raises 410 or 404
            if not token_matches(token, meta["tokens"]):
                raise Forbidden(data_id)
            self._evict(data_id, "deleted")

    @property
    def bytes(self) -> int:
        return sum(size for _, _, size, _ in self._entries())
