"""From an upload's bytes to a data set: the format detected from the content (or
insisted on with ``format=``), never from a file name.

Compressed files are refused, not opened: nothing here decompresses, so a small archive
cannot expand into gigabytes (a "zip bomb") however it is named or labelled.
"""
from __future__ import annotations

from ..errors import ParameterError
from . import csv_formats, merl
from .dataset import BrdfData, TermData, samples_data

FORMATS = {
    "merl": "MERL .binary (int32 dimensions 90 90 180, then R, G, B doubles)",
    "samples_csv": "CSV of BRDF samples (theta_i_deg, phi_i_deg, theta_o_deg, phi_o_deg, f "
                   "or f_r, f_g, f_b)",
    "term_csv": "CSV of one term (theta_deg with D, G1, F, or mu with E)",
}
#: leading bytes of compressed containers (their published magic numbers)
ARCHIVES = {b"PK\x03\x04": "a zip archive", b"PK\x05\x06": "an empty zip archive",
            b"\x1f\x8b": "gzip data", b"BZh": "bzip2 data", b"\xfd7zXZ\x00": "xz data",
            b"7z\xbc\xaf\x27\x1c": "a 7-Zip archive", b"\x28\xb5\x2f\xfd": "zstd data"}
#: bytes read to decide whether an upload is text
SNIFF_BYTES = 4096


def _error(message: str, param: str = "file") -> ParameterError:
    return ParameterError(param, message, loc="body" if param == "file" else "query")


def detect(content: bytes) -> str:
    """The format of an upload, from its first bytes."""
    if not content:
        raise _error("the file is empty")
    for magic, what in ARCHIVES.items():
        if content.startswith(magic):
            raise _error(f"the file is {what}; upload the uncompressed file (compressed uploads "
                         f"are not opened)")
    if merl.looks_like(content):
        return "merl"
    text = _text(content[:SNIFF_BYTES], partial=len(content) > SNIFF_BYTES)
    if text is None:
        raise _error(f"not a known format: the file is neither text nor a MERL .binary (whose "
                     f"header is the int32 dimensions 90 90 180); formats: {'; '.join(FORMATS.values())}")
    return "term_csv" if csv_formats.kind_of(csv_formats.parse_header(text)) == "term" else "samples_csv"


def _text(content: bytes, partial: bool = False) -> str | None:
    """The content as UTF-8 text (without a byte-order mark), or None if it is not text."""
    if b"\x00" in content:
        return None
    try:
        return content.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        if partial and exc.start >= len(content) - 3:   # a character cut by the sniff window
            return content[:exc.start].decode("utf-8-sig")
        return None


def load(content: bytes, format: str | None = None):
    """A BrdfData or TermData from an upload, in ``format`` if given."""
    if format is not None and format not in FORMATS:
        raise _error(f"format must be one of {', '.join(FORMATS)}; got {format!r}", "format")
    chosen = format or detect(content)
    if not content:
        raise _error("the file is empty")
    if chosen == "merl":
        return BrdfData("merl", ("r", "g", "b"), len(content), table=merl.read(content))
    text = _text(content)
    if text is None:
        raise _error(f"format={chosen} is CSV, UTF-8 text; this file is not text")
    table = csv_formats.parse(text)
    kind = csv_formats.kind_of(table)
    if chosen == "samples_csv":
        angles, channels, f = csv_formats.samples(table)
        return samples_data(angles, channels, f, len(content))
    if kind != "term":
        raise _error("format=term_csv needs a theta_deg or mu column; the header has "
                     f"{', '.join(table.columns)}")
    axis, x, terms = csv_formats.term(table)
    return TermData("term_csv", axis, x, terms, len(content))
