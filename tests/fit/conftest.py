# The app and client fixtures of the data-set tests: a fit needs an uploaded data set.
from tests.datasets.conftest import SETTINGS, app, client  # noqa: F401
