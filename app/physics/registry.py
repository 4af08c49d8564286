"""One registration idiom for every physics registry: NDFs, maskings, G2 forms, Fresnel.

A registry is a dict from an entry's ``name`` to the entry (a class or a frozen
dataclass instance); ``register`` adds one (usable as a class decorator) and refuses a
name twice. Entries with a ``menu_order`` are kept in menu order, so the API and the
page list them as declared. A package of one-file models calls :func:`import_modules`
once, so that adding a model is adding its file.
"""
from __future__ import annotations

import importlib
import pkgutil
from typing import Generic, TypeVar

T = TypeVar("T")

#: bumped by every change of any registry: what is derived from all of them (a model
#: family's query names) is recomputed after a change, and read from memory otherwise
_generation = [0]


def generation() -> int:
    """How many times any registry has changed in this process."""
    return _generation[0]


class Registry(dict, Generic[T]):
    def __init__(self, kind: str):
        super().__init__()
        self.kind = kind

    def register(self, entry: T) -> T:
        if entry.name in self:
            raise ValueError(f"{self.kind} {entry.name!r} registered twice")
        self[entry.name] = entry
        _generation[0] += 1
        if any(hasattr(e, "menu_order") for e in self.values()):
            ordered = sorted(self.items(), key=lambda kv: (getattr(kv[1], "menu_order", 100), kv[0]))
            self.clear()
            self.update(ordered)
        return entry

    def unregister(self, name: str) -> None:
        """Remove an entry (tests that register a throwaway model clean up with it)."""
        del self[name]
        _generation[0] += 1


def import_modules(package_name: str, package_path, skip: tuple[str, ...] = ()) -> None:
    """Import every module of a package (each registers its models on import)."""
    for info in sorted(pkgutil.iter_modules(package_path), key=lambda i: i.name):
        if info.name not in skip:
            importlib.import_module(f"{package_name}.{info.name}")
