"""The app client the export tests use (one per session)."""
from tests.export.conftest import client  # noqa: F401  (a fixture, shared)
