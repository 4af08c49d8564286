"""The policy of a data-set store shared by every worker, over any :class:`Files`.

Content-addressed: ``<id>.npz`` holds a data set's arrays, ``<id>.json`` its format,
summary, owner (the client that uploaded it first) and the hashes of its delete tokens.
Bounded in bytes (``max_bytes``, the ``.npz`` files): the least recently used data set
goes first, leaving ``<id>.gone`` with the reason, so a later GET answers 410 "expired
(why)" instead of 404; at most REMEMBERED_EVICTIONS such records are kept, the oldest
forgotten first, as the memory store does. A per-client quota (``client_bytes``): an
upload first evicts its own client's oldest data sets beyond the quota, so one client
alone holds at most ``client_bytes`` and cannot push out more than that of anyone else's.
Deleting needs a token the upload answered (a secret, stored only as its hash), not the
id alone: the id is a hash of public content.

The backends differ only in their file operations (:class:`Files`): a directory
(app/datasets/disk_store.py) or any fsspec URL (app/datasets/fsspec_store.py). The
interface (``put``, ``get``, ``delete``, ``in``, ``bytes``) is the memory store's, plus
the client and token.
"""
from __future__ import annotations

import contextlib
import json
import secrets
import zipfile
from typing import NamedTuple, Protocol

from ..errors import TooLarge
from .store import REMEMBERED_EVICTIONS, Expired, Forbidden, Unknown, token_hash, token_matches
from .stored_form import decode, encode

#: the file of each kind of record, after the id
DATA, META, GONE = ".npz", ".json", ".gone"
#: what decoding a damaged data set raises (a truncated zip, a missing array or key)
DAMAGED = (ValueError, KeyError, zipfile.BadZipFile)
#: the 410's reason for a data set whose files no longer decode: writes are whole, so only
#: other hands (an operator, the storage itself) damage one
DAMAGED_REASON = "its stored file was damaged"


class Files(Protocol):
    """Flat named files (``<id><suffix>``): what a backend gives the store."""

    def list(self) -> dict[str, tuple[int, float]]:
        """name → (bytes, last use: its write or its latest ``touch``) of every file."""

    def read(self, name: str) -> bytes:
        """The whole file; OSError (FileNotFoundError) when it is not there."""

    def read_many(self, names: list[str]) -> dict[str, bytes]:
        """The files of ``names`` that are there (in one round trip where it can)."""

    def write(self, name: str, content: bytes) -> None:
        """Replace the file at once: a reader sees the old content, or the new, whole."""

    def remove(self, name: str) -> None:
        """Remove the file (and what ``touch`` recorded of it); nothing if it is not there."""

    def exists(self, name: str) -> bool: ...

    def touch(self, name: str) -> None:
        """Record a use of the file now (``list`` then shows it)."""

    def locked(self) -> contextlib.AbstractContextManager:
        """Exclusive among the writers this backend can reach (see each backend)."""

    def clean(self) -> None:
        """Remove what writers that died left behind."""


class Entry(NamedTuple):
    """A stored data set, as the eviction order sees it (sorted: least recently used first)."""
    last_use: float
    data_id: str
    size: int
    client: str


class SharedDatasetStore:
    """id → (data set, summary) in ``files``, at most ``max_bytes`` held, at most
    ``client_bytes`` per client."""

    def __init__(self, files: Files, max_bytes: int, client_bytes: int | None = None):
        self.files = files
        self.max_bytes = max_bytes
        self.client_bytes = client_bytes or max_bytes

    # -- records ------------------------------------------------------------------------
    def _entries(self, listing: dict[str, tuple[int, float]]) -> list[Entry]:
        """Every stored data set, least recently used first."""
        ids = [name[:-len(DATA)] for name in listing
               if name.endswith(DATA) and name[:-len(DATA)] + META in listing]
        metas = self.files.read_many([i + META for i in ids])
        out = []
        for data_id in ids:
            try:
                client = json.loads(metas[data_id + META]).get("client", "")
            except (KeyError, ValueError):
                continue                                # removed or damaged since the listing
            size, last_use = listing[data_id + DATA]
            out.append(Entry(last_use, data_id, size, client))
        return sorted(out)

    def _read_meta(self, data_id: str) -> dict | None:
        try:
            return json.loads(self.files.read(data_id + META))
        except (OSError, ValueError):
            return None

    def _evict(self, data_id: str, why: str) -> None:
        self.files.write(data_id + GONE, why.encode())
        for suffix in (DATA, META):
            self.files.remove(data_id + suffix)

    def _forget_oldest_evictions(self, listing: dict[str, tuple[int, float]], new: int) -> None:
        """Keep at most REMEMBERED_EVICTIONS ``.gone`` records, the ``new`` ones written
        since ``listing`` included (each is a file, and every listing reads them all)."""
        gone = sorted((use, name) for name, (_, use) in listing.items() if name.endswith(GONE))
        for _, name in gone[:max(0, len(gone) + new - REMEMBERED_EVICTIONS)]:
            self.files.remove(name)

    # -- the store's interface ----------------------------------------------------------
    def __contains__(self, data_id: str) -> bool:
        return self.files.exists(data_id + META) and self.files.exists(data_id + DATA)

    def put(self, data_id: str, data, summary: dict, client: str = "") -> str:
        """Store the data set (once per content) and answer a new delete token for it."""
        meta, content = encode(data)
        limit = min(self.max_bytes, self.client_bytes)
        if len(content) > limit:
            raise TooLarge("file", f"this data set needs {len(content)} bytes stored; a client may "
                                   f"hold {limit} (settings BRDF_MAX_DATASETS_BYTES and the "
                                   "per-client quota)", loc="body")
        token = secrets.token_urlsafe(16)
        with self.files.locked():
            self.files.clean()
            old = self._read_meta(data_id)
            if old is not None and self.files.exists(data_id + DATA):
                old["tokens"].append(token_hash(token))   # the same content: one more owner
                self.files.write(data_id + META, json.dumps(old).encode())
                self.files.touch(data_id + DATA)
                return token
            listing = self.files.list()
            entries = [e for e in self._entries(listing) if e.data_id != data_id]
            evicted = 0
            own = sum(e.size for e in entries if e.client == client)
            for e in [e for e in entries if e.client == client]:   # its own, oldest first
                if own + len(content) <= self.client_bytes:
                    break
                self._evict(e.data_id, f"evicted, the oldest of its client's data sets, to keep "
                                       f"that client within its quota of {self.client_bytes} bytes")
                own -= e.size
                entries.remove(e)
                evicted += 1
            total = sum(e.size for e in entries)
            for e in entries:                                  # then anyone's, least recently used
                if total + len(content) <= self.max_bytes:
                    break
                self._evict(e.data_id, f"evicted, least recently used, to keep the store within "
                                       f"BRDF_MAX_DATASETS_BYTES={self.max_bytes}")
                total -= e.size
                evicted += 1
            self._forget_oldest_evictions(listing, evicted)
            self.files.write(data_id + DATA, content)
            self.files.write(data_id + META, json.dumps(
                {**meta, "summary": summary, "client": client, "tokens": [token_hash(token)]}).encode())
            self.files.remove(data_id + GONE)
        return token

    def get(self, data_id: str, param: str = "data", loc: str = "body") -> tuple:
        """(data set, summary); 410 with the reason for an evicted or deleted id, 404 for an
        unknown one."""
        meta = self._read_meta(data_id)
        content = None
        if meta is not None:
            with contextlib.suppress(OSError):                # evicted between the two reads
                content = self.files.read(data_id + DATA)
        if content is not None:
            try:
                data, info = decode(meta, content), meta["summary"]
            except DAMAGED:                 # written whole, so changed by other hands: 410
                with self.files.locked():  # and the reason, and an upload stores it anew
                    self._evict(data_id, DAMAGED_REASON)
                raise Expired(data_id, DAMAGED_REASON, param, loc) from None
            self.files.touch(data_id + DATA)                  # the LRU's "last used"
            return data, info
        try:
            why = self.files.read(data_id + GONE).decode()
        except OSError:
            raise Unknown(data_id, param, loc) from None
        raise Expired(data_id, why, param, loc)

    def delete(self, data_id: str, token: str | None = None, param: str = "data_id",
               loc: str = "path") -> None:
        with self.files.locked():
            meta = self._read_meta(data_id)
            if meta is None:
                self.get(data_id, param, loc)                 # raises 410 or 404
            if not token_matches(token, meta["tokens"]):
                raise Forbidden(data_id)
            self._evict(data_id, "deleted")

    @property
    def bytes(self) -> int:
        return sum(e.size for e in self._entries(self.files.list()))
