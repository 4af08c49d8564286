"""Where the installed package keeps the page.

A wheel, ``pip install .`` and ``pip install git+…`` install the repository's top-level
``static/`` as the package ``app.static`` (pyproject.toml maps it); a source checkout
run in place has it beside ``app/``. ``BRDF_STATIC_DIR`` overrides both (a page under
development elsewhere).
"""
from __future__ import annotations

from importlib import resources
from pathlib import Path

from .config import environment


def static_dir() -> Path:
    """The page's directory: BRDF_STATIC_DIR, else the installed app/static, else the
    checkout's static/ beside app/."""
    given = environment().static_dir
    if given:
        return Path(given)
    installed = resources.files(__package__) / "static"
    if installed.is_dir():
        return Path(str(installed))
    return Path(__file__).resolve().parent.parent / "static"
