"""Refresh the images in docs/ (the README's screenshots) from the browser tests that take them.

    BRDF_STATIC_DIR=$PWD/static python bench/screenshots.py

Runs those tests with BRDF_SCREENSHOT_DIR=docs/ (tests/e2e/conftest.py's `shots` fixture),
so each image is taken by the one test that also checks what it shows; a plain test run
writes them to a temporary directory and leaves the checkout as it was. Needs Chromium
(tests/e2e/conftest.py). Prints the images written.
"""
from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
#: the tests that take the README's images (docs/<name>.png each)
TESTS = [
    "tests/e2e/test_page_modules.py::test_page_screenshot",
    "tests/e2e/test_page_modules.py::test_phone_shows_plots_above_their_controls",
    "tests/e2e/test_page_modules.py::test_panel_png_is_slide_sized_and_named_after_its_parameters",
    "tests/e2e/test_page_modules.py::test_embed_with_controls_fits_its_frame",
    "tests/e2e/test_exports.py::test_gallery_renders_and_every_link_opens_its_state",
    "tests/e2e/test_exports.py::test_phone_portrait_has_no_sideways_scroll",
    "tests/e2e/test_models_ui.py::test_compare_tails_and_screenshot",
    "tests/e2e/test_data_overlay.py::test_a_measured_file_opened_fitted_and_its_fit_loaded",
]


def main() -> int:
    started = time.time()
    env = {**os.environ, "BRDF_SCREENSHOT_DIR": str(DOCS)}
    code = subprocess.call([sys.executable, "-m", "pytest", "-q", "-n", "0", "-p", "no:cacheprovider", *TESTS],
                           cwd=ROOT, env=env)
    for png in sorted(DOCS.glob("*.png")):
        if png.stat().st_mtime >= started:
            print(f"wrote {png.relative_to(ROOT)}")
    return code


if __name__ == "__main__":
    sys.exit(main())
