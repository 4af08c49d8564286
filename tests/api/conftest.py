import warnings

import pytest

with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)
    from fastapi.testclient import TestClient

from app.config import Settings
from tests.budget import settings_for_tests
from app.main import create_app


@pytest.fixture(scope="session")
def client():
    return TestClient(create_app(settings_for_tests()))


@pytest.fixture
def small_client():
    """An app with tiny limits, to test that limits are enforced and named."""
    return TestClient(create_app(Settings(max_curve_points=50, max_grid_points=100,
                                          max_query_list=4, max_batch=8, max_albedo_points=5)))
