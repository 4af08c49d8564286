"""The GPU panel's user-BRDF section driven as a user drives it, shared by the .brdf tests
(test_gpu_brdf.py, test_gpu_brdf_format.py, test_gpu_brdf_editor.py)."""
from __future__ import annotations

from pathlib import Path
from urllib.parse import urlencode

#: our own .brdf files, in the format of Disney's BRDF Explorer
BRDF_DIR = Path(__file__).resolve().parent / "brdf"
WALTER = BRDF_DIR / "walter_ggx_dielectric.brdf"
#: a D term file: GGX D(h) alone (its α the parameter `alpha`, default TWIN's 0.3)
D_GGX = BRDF_DIR / "d_ggx.brdf"
#: the registry model Walter's file writes (GGX, separable Smith, dielectric Fresnel)
TWIN = {"ndf": "ggx", "masking": "smith", "g2": "separable", "fresnel": "dielectric", "ior": 1.5, "alpha": 0.3}
READY = "() => window.__gpu && window.__gpu.ok"
LOADED = "() => window.__userBrdf.loaded && window.__userBrdf.measureCount > 0"


def open_gpu_page(page, model=TWIN):
    """The page with the GPU panel shown and ready, drawing ``model``."""
    page.goto("/?" + urlencode({**model, "show": "gpu"}))
    page.wait_for_function(READY, timeout=60_000)


def load_brdf(page, path: Path | None = None, *, name="x.brdf", text: str | None = None):
    """A .brdf file (or its ``text``) through the page's file input, as a user picks one."""
    payload = {"name": name, "mimeType": "text/plain",
               "buffer": (text.encode() if text is not None else path.read_bytes())}
    page.set_input_files("#gpu-brdf-file", files=[payload])
