"""A module whose import takes START_SECONDS: a heavy-pool worker that warms with it
starts at least that slowly (tests/robustness/test_heavy_pool.py), whatever the load."""
import time

START_SECONDS = 3.0

time.sleep(START_SECONDS)
