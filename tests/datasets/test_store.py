"""The data-set store: bounded in bytes, least recently used first, expired ids named."""
from dataclasses import dataclass

import pytest

from app.datasets.store import DatasetStore, content_id
from app.errors import ParameterError


@dataclass
class Blob:
    nbytes: int


def test_least_recently_used_goes_first_and_says_so():
    store = DatasetStore(max_bytes=100)
    store.put("a", Blob(40), {})
    store.put("b", Blob(40), {})
    store.get("a")                       # b is now the least recently used
    store.put("c", Blob(40), {})
    assert "a" in store and "c" in store and "b" not in store
    assert store.bytes == 80
    with pytest.raises(ParameterError) as info:
        store.get("b")
    assert info.value.status == 410 and "least recently used" in info.value.message
    assert "BRDF_MAX_DATASETS_BYTES=100" in info.value.message


def test_unknown_deleted_and_too_large():
    store = DatasetStore(max_bytes=100)
    with pytest.raises(ParameterError) as info:
        store.get("x")
    assert info.value.status == 404
    token = store.put("a", Blob(10), {})
    with pytest.raises(ParameterError) as refused:      # the id alone is public content
        store.delete("a")
    assert refused.value.status == 403 and refused.value.param == "token"
    store.delete("a", token)
    with pytest.raises(ParameterError, match="deleted") as info:
        store.get("a")
    assert info.value.status == 410
    with pytest.raises(ParameterError) as info:
        store.put("big", Blob(101), {})
    assert info.value.status == 413 and "BRDF_MAX_DATASETS_BYTES" in info.value.message
    store.put("a", Blob(10), {})         # uploaded again: alive, not expired
    assert "a" in store


def test_ids_are_content_hashes():
    assert content_id("merl", b"x") == content_id("merl", b"x")
    assert content_id("merl", b"x") != content_id("samples_csv", b"x")
    assert len(content_id("merl", b"x")) == 32
