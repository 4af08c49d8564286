"""No module tests which model family a model is, except the family's own package: the
page and every module read families, their parameters and capabilities from the model
registry (app/model/registry.py, GET /api/v1/models). Searched: app/ (Python) and
static/ (JS) for a comparison with a family's name (``== "principled"``,
``model !== "microfacet"``, ``in ("principled", …)``) and, in JS, for a family's name as
a string at all (a constant that names one, like ``PRINCIPLED = "principled"``)."""
from __future__ import annotations

import re
from pathlib import Path

from app.model import families

ROOT = Path(__file__).resolve().parents[1]
#: each family's own package, where its name may be written
OWN = {"microfacet": ("app/model/",), "principled": ("app/principled/",)}


def _compared(name: str) -> re.Pattern:
    quoted = rf"""["']{name}["']"""
    return re.compile(rf"""(?:[=!]==?\s*{quoted}|{quoted}\s*[=!]==?|\bin\s*[(\[{{][^)\]}}]*{quoted}|case\s+{quoted})""")


def _files():
    yield from ROOT.glob("app/**/*.py")
    yield from ROOT.glob("static/**/*.js")


def test_no_model_name_test_outside_the_family():
    found = []
    for family in families():
        compared, anywhere = _compared(family), re.compile(rf"""["'`]{family}["'`]""")
        for path in _files():
            rel = path.relative_to(ROOT).as_posix()
            if rel.startswith(OWN.get(family, ())):
                continue
            text = path.read_text(encoding="utf-8")
            pattern = anywhere if rel.endswith(".js") else compared
            found += [f"{rel}:{text.count(chr(10), 0, m.start()) + 1}: {m.group(0)}" for m in pattern.finditer(text)]
    assert found == []


def test_the_search_finds_what_it_forbids():
    pattern = _compared("principled")
    for line in ('if model == "principled":', "x != 'principled'", 'if m in ("microfacet", "principled")',
                 'if (s.model === "principled")'):
        assert pattern.search(line), line
    assert not pattern.search('Entry("principled-metallic", ...)')
