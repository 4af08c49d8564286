"""Uploaded data sets in memory, bounded in bytes: the least recently used goes first.

Ids are content hashes (of the format and the bytes), so nothing is ever named by the
user and the same upload gets the same id. An id that was evicted is remembered (a
bounded list of ids, not their data) so that a request for it can say "expired" rather
than "unknown".
"""
from __future__ import annotations

import hashlib
import hmac
import secrets
import threading
from collections import OrderedDict

from ..errors import ParameterError, TooLarge

#: evicted ids remembered to answer "expired" (32 hex characters each: ~1 MB at most)
REMEMBERED_EVICTIONS = 16_384


class Expired(ParameterError):
    """An id that was in the store and was evicted (least recently used) or deleted."""

    def __init__(self, data_id: str, why: str, param: str, loc: str):
        super().__init__(param, f"data set {data_id} has expired ({why}); upload it again",
                         status=410, loc=loc)


class Unknown(ParameterError):
    def __init__(self, data_id: str, param: str, loc: str):
        super().__init__(param, f"no data set has id {data_id!r}; upload one with POST "
                                "/api/v1/datasets", status=404, loc=loc)


class Forbidden(ParameterError):
    """A delete without the token the upload answered (the id alone is a hash of content
    anyone may hold)."""

    def __init__(self, data_id: str):
        super().__init__("token", f"deleting data set {data_id} needs the token its upload "
                                  "answered (query parameter token)", status=403, loc="query")


def token_hash(token: str) -> str:
    """What a store keeps of a delete token: its SHA-256, never the token."""
    return hashlib.sha256(token.encode()).hexdigest()


def token_matches(token: str | None, hashes) -> bool:
    return bool(token) and any(hmac.compare_digest(token_hash(token), h) for h in hashes)


def content_id(format: str, content: bytes) -> str:
    return hashlib.blake2b(format.encode() + b"\0" + content, digest_size=16).hexdigest()


class DatasetStore:
    """id → (data set, summary), at most ``max_bytes`` of arrays held."""

    def __init__(self, max_bytes: int):
        self.max_bytes = max_bytes
        self._items: OrderedDict[str, tuple] = OrderedDict()
        self._tokens: dict[str, list[str]] = {}
        self._gone: OrderedDict[str, str] = OrderedDict()
        self._bytes = 0
        self._lock = threading.Lock()

    def __contains__(self, data_id: str) -> bool:
        with self._lock:
            return data_id in self._items

    def put(self, data_id: str, data, summary: dict, client: str = "") -> str:
        """Keep the data set (once per content) and answer a new delete token for it
        (``client`` is the disk store's quota key; memory has no per-client quota)."""
        token = secrets.token_urlsafe(16)
        size = data.nbytes
        if size > self.max_bytes:
            raise TooLarge("file", f"this data set needs {size} bytes in memory; the store holds "
                                   f"{self.max_bytes} (setting BRDF_MAX_DATASETS_BYTES)", loc="body")
        with self._lock:
            self._tokens.setdefault(data_id, []).append(token_hash(token))
            if data_id in self._items:
                self._items.move_to_end(data_id)
                return token
            while self._bytes + size > self.max_bytes:
                old, (old_data, _) = self._items.popitem(last=False)
                self._bytes -= old_data.nbytes
                self._tokens.pop(old, None)
                self._forget(old, f"evicted, least recently used, to keep the store within "
                                  f"BRDF_MAX_DATASETS_BYTES={self.max_bytes}")
            self._items[data_id] = (data, summary)
            self._gone.pop(data_id, None)
            self._bytes += size
        return token

    def get(self, data_id: str, param: str = "data", loc: str = "body") -> tuple:
        """(data set, summary); 410 for an expired id, 404 for an unknown one (naming the
        request's ``param`` at ``loc``)."""
        with self._lock:
            item = self._items.get(data_id)
            if item is not None:
                self._items.move_to_end(data_id)
                return item
            why = self._gone.get(data_id)
        raise Expired(data_id, why, param, loc) if why else Unknown(data_id, param, loc)

    def delete(self, data_id: str, token: str | None = None, param: str = "data_id",
               loc: str = "path") -> None:
        with self._lock:
            if data_id in self._items and not token_matches(token, self._tokens.get(data_id, ())):
                raise Forbidden(data_id)
            item = self._items.pop(data_id, None)
            if item is not None:
                self._tokens.pop(data_id, None)
                self._bytes -= item[0].nbytes
                self._forget(data_id, "deleted")
                return
            why = self._gone.get(data_id)
        raise Expired(data_id, why, param, loc) if why else Unknown(data_id, param, loc)

    def _forget(self, data_id: str, why: str) -> None:
        self._gone[data_id] = why
        while len(self._gone) > REMEMBERED_EVICTIONS:
            self._gone.popitem(last=False)

    @property
    def bytes(self) -> int:
        return self._bytes
