"""Every environment variable the application reads is read in app/config.py, once, into
the Settings: nowhere else in app/ reads one (the README documents them from there)."""
from __future__ import annotations

import ast
from dataclasses import fields
from pathlib import Path

import pytest

from app.config import Settings, variable

APP = Path(__file__).resolve().parents[2] / "app"
#: reads outside app/config.py that another engineer's area still has, with the issue
#: that moves them (the lead empties this list after merging)
KNOWN = {}


def _reads(path: Path) -> list[int]:
    """Lines that read a variable: os.environ.get(...), os.environ[...], os.getenv(...)
    (passing the whole environment on to a child process is not a read)."""
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        target = node.func if isinstance(node, ast.Call) else node.value if isinstance(node, ast.Subscript) else None
        text = ast.unparse(target) if target is not None else ""
        if text in ("os.environ.get", "os.getenv", "os.environ", "environ.get", "getenv"):
            out.append(node.lineno)
    return out


def test_no_module_but_config_reads_the_environment():
    found = {str(p.relative_to(APP.parent)): lines for p in sorted(APP.rglob("*.py"))
             if p != APP / "config.py" and (lines := _reads(p))}
    assert sorted(found) == sorted(KNOWN), found


def test_every_setting_is_read_from_its_variable(monkeypatch):
    """Each field from its documented variable, with its type."""
    given = {"str": "/somewhere", "bool": "0", "int": "7", "float": "2.5", "tuple[str, ...]": "a, b"}
    for f in fields(Settings):
        monkeypatch.setenv(variable(f.name), given[f.type if isinstance(f.type, str) else f.type.__name__])
    s = Settings.from_env()
    assert s.static_dir == "/somewhere" and s.chromium == "/somewhere" and s.fast is False
    assert s.max_seconds == 2.5 and s.max_batch == 7 and s.cors_origins == ("a", "b")
    assert s.cache_directory() == Path("/somewhere")


@pytest.mark.parametrize("home, expected", [("", Path.home() / ".cache" / "brdf-explorer"),
                                            ("/x", Path("/x/brdf-explorer"))])
def test_the_tables_go_under_the_xdg_cache_when_no_directory_is_set(monkeypatch, home, expected):
    monkeypatch.delenv("BRDF_CACHE_DIR", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", home)
    assert Settings.from_env().cache_directory() == expected


def test_a_switch_is_off_only_at_zero(monkeypatch):
    for raw, on in (("0", False), ("1", True), ("yes", True)):
        monkeypatch.setenv("BRDF_FAST", raw)
        assert Settings.from_env().fast is on
