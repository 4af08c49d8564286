import pytest
from fastapi.testclient import TestClient

from app.main import create_app
from tests.budget import settings_for_tests


@pytest.fixture(scope="module")
def client():
    return TestClient(create_app(settings_for_tests()))
