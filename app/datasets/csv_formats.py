"""The two CSV formats: BRDF samples (a renderer's or a shader's dump) and one term
against its angle. A header row names the columns (any order, case-insensitive, spaces
ignored); ``#`` lines are comments; numbers are decimal, comma-separated.

- samples: ``theta_i_deg, phi_i_deg, theta_o_deg, phi_o_deg`` and ``f`` or
  ``f_r, f_g, f_b`` (f in 1/sr, no cosine; i = light l, o = view v);
- term: ``theta_deg`` with any of ``D``, ``G1``, ``F``; or ``mu`` with ``E``.
"""
from __future__ import annotations

import difflib
import io
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError

ANGLES = ("theta_i_deg", "phi_i_deg", "theta_o_deg", "phi_o_deg")
SAMPLE_CHANNELS = {("f",): ("f",), ("f_r", "f_g", "f_b"): ("r", "g", "b")}
TERM_AXES = {"theta_deg": ("D", "G1", "F"), "mu": ("E",)}
KNOWN = set(ANGLES) | {"f", "f_r", "f_g", "f_b"} | set(TERM_AXES) | {"D", "G1", "F", "E"}
#: names other tools give the columns, and this format's name for each (a hint, never a
#: silent rename: f_r and r are not the same quantity in every tool)
ALIASES = {"r": "f_r", "g": "f_g", "b": "f_b", "red": "f_r", "green": "f_g", "blue": "f_b",
           "brdf": "f", "value": "f", "theta_i": "theta_i_deg", "phi_i": "phi_i_deg",
           "theta_o": "theta_o_deg", "phi_o": "phi_o_deg", "theta": "theta_deg"}
#: separators other than the comma that a header may be written with, by name
OTHER_SEPARATORS = {";": "a semicolon ';'", "\t": "a tab", "|": "a bar '|'"}
#: ranges of the columns that have one (a polar angle past 90° is below the horizon)
RANGES = {"theta_i_deg": (0.0, 90.0), "theta_o_deg": (0.0, 90.0), "theta_deg": (0.0, 90.0),
          "mu": (0.0, 1.0)}


@dataclass(frozen=True)
class Table:
    """Parsed columns: name → float64 array, in file order."""
    columns: dict

    @property
    def rows(self) -> int:
        return len(next(iter(self.columns.values())))


def _error(message: str) -> ParameterError:
    return ParameterError("file", message, loc="body")


def _canonical(name: str) -> str:
    """A column name as spelled here: exact, else the one known name equal to it but for
    case (f, the BRDF, and F, Fresnel's factor, differ only by case: never mixed up)."""
    key = name.strip().replace(" ", "")
    if key in KNOWN:
        return key
    same = [known for known in KNOWN if known.lower() == key.lower()]
    return same[0] if len(same) == 1 else key


def _lines(text: str) -> list[str]:
    lines = [line for line in text.splitlines() if line.strip() and not line.lstrip().startswith("#")]
    if not lines:
        raise _error("the CSV has no header row and no data")
    return lines


def _header(line: str) -> list[str]:
    if "," not in line:
        for sep, name in OTHER_SEPARATORS.items():
            if sep in line:
                raise _error(f"the columns are separated by {name}; this format separates them "
                             f"with commas ','; save the file as comma-separated (decimal point "
                             f"'.'), e.g. {','.join(ANGLES)},f")
    header = [_canonical(h) for h in line.split(",")]
    if len(set(header)) != len(header):
        twice = next(h for h in header if header.count(h) > 1)
        raise _error(f"column {twice!r} appears twice in the header")
    unknown = [h for h in header if h not in KNOWN]
    if unknown:
        alias = ALIASES.get(unknown[0].lower())
        near = [alias] if alias else difflib.get_close_matches(unknown[0], sorted(KNOWN), n=1, cutoff=0.6)
        hint = f" (did you mean {near[0]!r}?)" if near else ""
        if alias and all(h.lower() in ALIASES for h in unknown) and len(unknown) > 1:
            hint = (f" (did you mean {', '.join(repr(ALIASES[h.lower()]) for h in unknown)} for "
                    f"{', '.join(repr(h) for h in unknown)}?)")
        raise _error(f"unknown column {unknown[0]!r}{hint}; the columns are {', '.join(ANGLES)} "
                     f"with f or f_r, f_g, f_b (BRDF samples), or theta_deg with D, G1, F, or "
                     f"mu with E (one term)")
    return header


def parse_header(text: str) -> Table:
    """The columns a CSV names, without its data (to tell the two formats apart)."""
    return Table({name: np.empty(0) for name in _header(_lines(text)[0])})


def parse(text: str) -> Table:
    """Header and numbers of a CSV; every value finite."""
    lines = _lines(text)
    header = _header(lines[0])
    if len(lines) < 2:
        raise _error("the CSV has a header row but no data rows")
    try:
        values = np.loadtxt(io.StringIO("\n".join(lines[1:])), delimiter=",", ndmin=2,
                            dtype=float)
    except ValueError as exc:
        raise _error(f"a data row is not {len(header)} comma-separated numbers: "
                     f"{str(exc).splitlines()[0][:200]}") from None
    if values.shape[1] != len(header):
        raise _error(f"the header names {len(header)} columns but the rows have {values.shape[1]}")
    bad = ~np.isfinite(values)
    if bad.any():
        row, col = (int(x[0]) for x in np.nonzero(bad))
        raise _error(f"{header[col]} must be a finite number; data row {row + 1} has "
                     f"{values[row, col]}")
    columns = {name: values[:, k].copy() for k, name in enumerate(header)}
    for name, (lo, hi) in RANGES.items():
        if name in columns:
            _check_range(columns[name], name, lo, hi)
    return Table(columns)


def _check_range(x: np.ndarray, name: str, lo: float, hi: float) -> None:
    outside = (x < lo) | (x > hi)
    if outside.any():
        row = int(np.argmax(outside))
        raise _error(f"{name} must be in [{lo:g}, {hi:g}]; data row {row + 1} has {x[row]:g}")


def _non_negative(x: np.ndarray, name: str, why: str) -> None:
    if (x < 0).any():
        row = int(np.argmax(x < 0))
        raise _error(f"{name} must be ≥ 0 ({why}); data row {row + 1} has {x[row]:g}")


def samples(table: Table) -> tuple[dict, tuple[str, ...], np.ndarray]:
    """(angles in degrees by name, channel names, f[channel, row]) of a samples CSV."""
    cols = table.columns
    missing = [a for a in ANGLES if a not in cols]
    found = [key for key in SAMPLE_CHANNELS if all(k in cols for k in key)]
    if missing or not found:
        what = missing[0] if missing else "f (or f_r, f_g, f_b)"
        raise _error(f"a BRDF samples CSV needs the columns {', '.join(ANGLES)} and f (or f_r, "
                     f"f_g, f_b); {what} is missing (the header has {', '.join(cols)})")
    key = found[-1]
    extra = [c for c in cols if c not in ANGLES and c not in key]
    if extra:
        raise _error(f"column {extra[0]!r} does not belong in a BRDF samples CSV")
    f = np.stack([cols[k] for k in key])
    for k in key:
        _non_negative(cols[k], k, "a BRDF is not negative; leave out rows that were not measured")
    return {a: cols[a] for a in ANGLES}, SAMPLE_CHANNELS[key], f


def term(table: Table) -> tuple[str, np.ndarray, dict]:
    """(axis name, axis values, {term: values}) of a term CSV."""
    cols = table.columns
    axes = [a for a in TERM_AXES if a in cols]
    if len(axes) != 1:
        raise _error("a term CSV has one angle column, theta_deg (with D, G1, F) or mu (with E); "
                     f"the header has {', '.join(cols)}")
    axis = axes[0]
    terms = {k: cols[k] for k in cols if k != axis}
    wrong = [k for k in terms if k not in TERM_AXES[axis]]
    if wrong or not terms:
        allowed = ", ".join(TERM_AXES[axis])
        what = f"column {wrong[0]!r} does not go with {axis}" if wrong else "no term column"
        raise _error(f"{what}: with {axis} the terms are {allowed}")
    for k, x in terms.items():
        _non_negative(x, k, f"{k} is a density or a ratio of areas or energies")
    return axis, cols[axis], terms


def kind_of(table: Table) -> str:
    """"samples" or "term", from the header."""
    return "term" if any(a in table.columns for a in TERM_AXES) else "samples"
