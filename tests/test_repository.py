"""What holds for the repository as a whole: small modules, short docstrings, and no pointer
to documents a user does not have (the project's own derivations live in docs/)."""
from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: The longest a module under app/ or static/ may be: one job per module.
MAX_LINES = 400
SOURCE = (".py", ".js", ".css", ".html")
#: The longest a docstring under app/ may be, counted from its opening quotes to its
#: closing ones: what and why; a derivation goes to docs/, a measurement to BENCHMARKS.md.
MAX_DOCSTRING_LINES = 15
#: A private working document, its section numbers (a parenthesised "3-17"), or the
#: internal sources it was drawn from; built from parts so that this file does not match
#: itself.
FOREIGN = re.compile("|".join([r"MATH" + r"\.md", r"\bseed " + r"\d{3}\b", r"\bseed " + r"\(",
                               r"\([23]" + r"-\d+\)"]))
TEXT = (".py", ".js", ".css", ".html", ".md", ".toml", ".txt", ".cfg", ".lua", ".sh")


def _files(*tops: str, suffixes=SOURCE) -> list[Path]:
    out = []
    for top in tops:
        path = ROOT / top
        out += [path] if path.is_file() else [p for p in sorted(path.rglob("*"))
                                             if p.is_file() and p.suffix in suffixes
                                             and "vendor" not in p.parts and "_generated" not in p.parts]
    return out


@pytest.mark.parametrize("top", ["app", "static"])
def test_no_module_is_longer_than_400_lines(top):
    files = _files(top)
    assert files
    long = {str(p.relative_to(ROOT)): n for p in files
            if (n := len(p.read_text(encoding="utf-8").splitlines())) > MAX_LINES}
    assert long == {}


def test_no_pointer_to_documents_outside_the_repository():
    """Code, API texts, tests, benchmarks and README cite papers by name and docs/ by
    section; nothing outside docs/ names a private document or its equation numbers."""
    files = _files("app", "static", "tests", "bench", "README.md", "BENCHMARKS.md",
                   "pyproject.toml", suffixes=TEXT)
    hits = [f"{p.relative_to(ROOT)}:{i}: {line.strip()[:80]}" for p in files
            for i, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1)
            if FOREIGN.search(line) and p.name != "test_readme.py"]
    assert hits == []


def test_every_folder_of_app_is_a_package_the_wheel_ships():
    """setup.py lists the packages find_packages finds: a folder of modules without an
    __init__.py (a namespace package) would work from the source tree and be missing from
    the installed wheel (app.environment and app.lut once were)."""
    folders = {p.parent for p in (ROOT / "app").rglob("*.py")
               if "_generated" not in p.parts and "__pycache__" not in p.parts}
    assert sorted(str(f.relative_to(ROOT)) for f in folders if not (f / "__init__.py").is_file()) == []


def test_no_docstring_is_longer_than_15_lines():
    """Every module, class and function docstring under app/ (the generated kernels aside)
    states what and why in at most MAX_DOCSTRING_LINES lines; a derivation goes to docs/,
    cited by section."""
    files = _files("app", suffixes=(".py",))
    assert files
    long = []
    for path in files:
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
                doc = ast.get_docstring(node, clean=False)
                if doc is not None and (n := len(doc.split("\n"))) > MAX_DOCSTRING_LINES:
                    long.append(f"{path.relative_to(ROOT)}: {getattr(node, 'name', '(module)')}, {n} lines")
    assert long == []
