"""The wheel ships the page: built from a copy of the source, installed into a fresh venv
(dependencies from the system's site-packages, the package itself only from the wheel),
served from another directory; /, a static module, the gallery and a figure answer.

This directory has no __init__.py: as a package pytest would import it as ``packaging``,
the name of the library pip and kaleido import."""
import os
import shutil
import subprocess
import sys
import urllib.request
import zipfile
from pathlib import Path

import pytest

from tests.live import free_port, stop, wait_until_up

ROOT = Path(__file__).resolve().parents[2]
#: What a source distribution or a git checkout holds that the build reads.
SOURCES = ["app", "static", "pyproject.toml", "setup.py", "README.md"]
#: Seconds the installed server may take to start: numba compiles its kernels first
#: (7-12 s cold on an idle machine, more on a loaded one).
START_SECONDS = 240


def _copy_sources(dst: Path) -> Path:
    src = dst / "src"
    src.mkdir()
    for name in SOURCES:
        path = ROOT / name
        if path.is_dir():
            shutil.copytree(path, src / name, ignore=shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc"))
        else:
            shutil.copy2(path, src / name)
    return src


def _build_wheel(src: Path, out: Path) -> Path:
    """pip wheel without build isolation when the installed setuptools can build wheels
    itself (≥ 70.1), else with it (pip then fetches setuptools from the index)."""
    import setuptools
    major, minor = (int(x) for x in setuptools.__version__.split(".")[:2])
    flags = ["--no-build-isolation"] if (major, minor) >= (70, 1) else []
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", *flags, "-q", "-w", str(out), str(src)],
                   check=True, timeout=600)
    wheels = list(out.glob("*.whl"))
    assert len(wheels) == 1
    return wheels[0]


def _get(url: str) -> tuple[int, bytes, str]:
    with urllib.request.urlopen(url, timeout=120) as r:
        return r.status, r.read(), r.headers.get("content-type", "")


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    tmp = tmp_path_factory.mktemp("wheel")
    return _build_wheel(_copy_sources(tmp), tmp / "dist")


def test_wheel_holds_the_page_and_the_gallery(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    shipped = {p.relative_to(ROOT).as_posix() for p in (ROOT / "static").rglob("*") if p.is_file()}
    assert shipped and {"app/" + name for name in shipped} <= names
    assert {"app/static/index.html", "app/static/gallery.html", "app/gallery/__init__.py", "app/gallery/cards.py",
            "app/data/example_ggx_samples.csv", "app/main.py"} <= names


def test_installed_wheel_serves_the_page_from_another_directory(wheel, tmp_path):
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], check=True, timeout=300)
    python = venv / "bin" / "python"
    subprocess.run([str(python), "-m", "pip", "install", "--no-deps", "--no-index", "-q", str(wheel)],
                   check=True, timeout=300)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "BRDF_STATIC_DIR")}
    where = subprocess.run([str(python), "-c", "import app, app.resources as r; print(app.__file__); print(r.static_dir())"],
                           cwd=elsewhere, env=env, capture_output=True, text=True, check=True, timeout=120)
    app_file, static = where.stdout.split()
    assert Path(app_file).is_relative_to(venv), app_file        # from the wheel, not the source tree
    assert Path(static).is_relative_to(venv), static
    port = free_port()
    server = subprocess.Popen([str(venv / "bin" / "brdf-explorer"), "serve", "--port", str(port)],
                              cwd=elsewhere, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    try:
        base = f"http://127.0.0.1:{port}"
        wait_until_up(base + "/", server, START_SECONDS)
        status, page, _ = _get(base + "/")
        assert status == 200 and b"<html" in page.lower()
        module = sorted((ROOT / "static").rglob("*.js"))[-1].relative_to(ROOT / "static").as_posix()
        status, body, kind = _get(f"{base}/static/{module}")
        assert status == 200 and body == (ROOT / "static" / module).read_bytes() and "javascript" in kind
        status, body, _ = _get(base + "/gallery")
        assert status == 200 and b"<html" in body.lower()
        status, body, kind = _get(base + "/api/v1/figures/lobe?n=31")
        assert status == 200 and kind.startswith("application/json") and b'"data"' in body
    finally:
        stop(server)
