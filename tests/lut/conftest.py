import warnings

import pytest

with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)
    from fastapi.testclient import TestClient

from app.main import create_app
from tests.budget import settings_for_tests


@pytest.fixture(scope="session")
def client():
    return TestClient(create_app(settings_for_tests()))
