"""Example data sets the server provides without an upload, so that the data overlays and
fits can be shown (the gallery's data-set and fit cards) and tried by anyone.

Each example is a file shipped in app/data/ and read like an upload; its id is the same
content hash an upload of that file gets, so it is fixed across workers and restarts.
:class:`WithExamples` answers an example's id from the file when the store does not hold
it (never uploaded here, or evicted since), and keeps it in the store from then on.
The examples are synthetic — written from a model by GET /api/v1/export/model.csv — and
say so: the project ships no measured data.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from . import formats, summary
from .store import Expired, Unknown, content_id

DATA = Path(__file__).resolve().parent.parent / "data"


@dataclass(frozen=True)
class Example:
    name: str
    file: str            # in app/data/
    format: str          # as POST /api/v1/datasets would detect it
    model: dict          # the model the file was written from (GET /api/v1/export/model.csv)
    grid: dict           # that export's n_theta, n_phi
    description: str


EXAMPLES: dict[str, Example] = {e.name: e for e in (
    Example("ggx-samples", "example_ggx_samples.csv", "samples_csv",
            {"ndf": "ggx", "alpha": 0.3, "f0": 0.9, "kd": 0}, {"n_theta": 10, "n_phi": 12},
            "synthetic BRDF samples of a metal-like surface written from GGX (α = 0.3, F₀ = 0.9, "
            "no diffuse term) by "
            "GET /api/v1/export/model.csv: θ_i, θ_o every 10°, φ_o every 30°"),
)}


def content(name: str) -> bytes:
    return (DATA / EXAMPLES[name].file).read_bytes()


@lru_cache(maxsize=None)
def example_id(name: str) -> str:
    """The id an upload of this example's file gets (a hash of its content)."""
    return content_id(EXAMPLES[name].format, content(name))


def named(data_id: str) -> str | None:
    """The example with this id, or None."""
    return next((n for n in EXAMPLES if example_id(n) == data_id), None)


def load(name: str) -> tuple:
    """(data set, summary) of an example, read as its upload would be."""
    data = formats.load(content(name), EXAMPLES[name].format)
    return data, summary.summarize(data)


class WithExamples:
    """A data-set store (memory or disk) that also answers the examples' ids."""

    def __init__(self, store):
        self.store = store

    def get(self, data_id: str, param: str = "data", loc: str = "body") -> tuple:
        try:
            return self.store.get(data_id, param, loc)
        except (Unknown, Expired):
            name = named(data_id)
            if name is None:
                raise
        data, info = load(name)
        self.store.put(data_id, data, info, client="examples")   # its token is dropped: no one deletes it
        return data, info

    def __getattr__(self, name):
        return getattr(self.store, name)

    def __contains__(self, data_id: str) -> bool:
        return data_id in self.store
