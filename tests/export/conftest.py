"""Exports: an app client, and ONE kaleido renderer (one headless Chromium) per test
session, shared by every image test and closed at the end."""
from __future__ import annotations

import csv
import io
import os
import warnings

import pytest

with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)
    from fastapi.testclient import TestClient

from tests.budget import settings_for_tests
from app.export.image import ImageRenderer, get_renderer
from app.main import create_app


@pytest.fixture(scope="session")
def client():
    return TestClient(create_app(settings_for_tests()))


@pytest.fixture(scope="session")
def renderer():
    r = ImageRenderer(os.environ.get("BRDF_CHROMIUM") or None)
    yield r
    r.close()


@pytest.fixture(scope="session")
def image_client(renderer):
    """An app whose image exports use the session's one browser."""
    app = create_app(settings_for_tests())
    app.dependency_overrides[get_renderer] = lambda: renderer
    return TestClient(app)


def read_csv(text: str) -> tuple[dict[str, str], list[str], list[list[str]]]:
    """(comment lines as name → value, header, rows) of an exported CSV."""
    comments, body = {}, []
    for line in text.splitlines():
        if line.startswith("#"):
            name, _, value = line[1:].partition(" = ")
            comments[name.strip()] = value.strip()
        else:
            body.append(line)
    rows = list(csv.reader(io.StringIO("\n".join(body))))
    return comments, rows[0], rows[1:]
