"""The physics tests' parametrisation (every NDF × every α pair) and random generator,
shared by the integration tests."""
from tests.physics.conftest import pytest_generate_tests, rng  # noqa: F401
