"""Your BRDF's D-like slice on the NDF panel (static/js/gpu/usercurves.js): f(l, v) at
l = v at θ_h from the normal (θ_d = 0, so h = l = v), Disney's BRDF Explorer's θ_h plot,
read back from the GPU at the NDF panel's own θ_m nodes and azimuth and added as a trace
"your BRDF: f at l = v (θ_d = 0)" through the panel's overlay.

References: the server's float64 NDF figure of the registry GGX for a D term file at the
same α (its BRDF returns D(h): at l = v it is D(θ_h), and with the panel's D·cos θ_m toggle
f·cos θ_h is D·cos θ_m); the closed form ρ/π for a Lambertian file. One page load.
"""
from __future__ import annotations

from urllib.parse import urlencode

import numpy as np
import pytest

from tests.e2e.test_gpu_user_views import FLOOR, REL, _array, _close, _get
from tests.e2e.user_brdf_page import D_GGX, LOADED, READY, TWIN, WALTER, load_brdf

pytestmark = pytest.mark.e2e

#: in Plotly's markup, as the figure's own names (the legend draws the subscripts)
LABEL = "your BRDF: f at l = v (θ<sub>d</sub> = 0)"
COS_LABEL = "your BRDF: f·cos θ<sub>h</sub> at l = v (θ<sub>d</sub> = 0)"
#: float32 arithmetic of the closed form ρ/π
F32 = 1e-5
RHO = 0.6
LAMBERT = f"""::begin parameters
float rho 0 1 {RHO}
::end parameters
::begin shader
vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) {{ return vec3(rho / 3.14159265358979); }}
::end shader
"""

TRACE = "() => window.__brdf.panel('ndf').figure.data.find((t) => t.meta && t.meta.role === 'user-brdf') || null"


def _trace(page, label, since=-1):
    """The NDF panel's user trace once it has this label and was drawn after count `since`."""
    page.wait_for_function(f"([label, n]) => {{ const t = ({TRACE})(); return t && t.name === label"
                           " && window.__userCurves.count > n && window.__brdf.pending() === 0; }",
                           arg=[label, since], timeout=60_000)
    return page.evaluate(f"({TRACE})()")


def _server_d(live_server, page, key):
    """The NDF panel's own curve as the server computed it (float64), at its URL now."""
    fig = _get(live_server, page.evaluate("() => window.__brdf.url('ndf')"))
    model = fig["data"][0]
    assert model["name"] == key
    return _array(model["x"]), _array(model["y"])


def test_user_brdf_dlike_slice_on_the_ndf_panel(page, page_log, live_server, shots):
    page.goto("/?" + urlencode({**TWIN, "show": "ndf,gpu"}))
    page.wait_for_function(READY, timeout=60_000)
    page.wait_for_function("() => window.__brdf.pending() === 0 && window.__brdf.panel('ndf').figure", timeout=60_000)

    # -- a D term file at the registry GGX's α: the trace is the panel's D, node for node
    load_brdf(page, D_GGX, name="d_ggx.brdf")
    page.wait_for_function(LOADED, timeout=60_000)
    assert page.evaluate("() => window.__userBrdf.values.alpha") == TWIN["alpha"]
    user = _trace(page, LABEL)
    theta, D = _server_d(live_server, page, "D(θ<sub>m</sub>)")
    assert np.array_equal(np.array(user["x"], dtype=float), theta)      # the panel's own θ_m
    err = _close(_array(user["y"]), D, REL, FLOOR * np.nanmax(D))
    print(f"D term file: {theta.size} θ_m over 0..90°, largest relative difference from the server's D {err:.2e}")
    assert err <= REL
    page.locator("section[data-panel=ndf]").screenshot(path=str(shots / "user-dlike-d-ggx.png"))

    # -- the panel's D·cos θ_m toggle: f·cos θ_h, against the server's D·cos θ_m
    n = page.evaluate("() => window.__userCurves.count")
    page.check("#ndf-cosine")
    user = _trace(page, COS_LABEL, n)
    theta, Dc = _server_d(live_server, page, "D(θ<sub>m</sub>)·cos θ<sub>m</sub>")
    assert np.array_equal(np.array(user["x"], dtype=float), theta)
    err = _close(_array(user["y"]), Dc, REL, FLOOR * np.nanmax(Dc))
    print(f"D term file, D·cos θ_m: largest relative difference {err:.2e}")
    assert err <= REL
    n = page.evaluate("() => window.__userCurves.count")
    page.uncheck("#ndf-cosine")
    _trace(page, LABEL, n)

    # -- the panel redrawn for a change that is not the trace's (the model's ior: same
    # θ_m nodes, azimuth and toggles): drawn again, not evaluated again
    n0, e0 = page.evaluate("() => [window.__userCurves.count, window.__userCurves.evaluations]")
    page.evaluate("""() => { const s = document.getElementById('dielectric-ior-slider'); s.value = '2';
                     s.dispatchEvent(new Event('input', {bubbles: true})); }""")
    page.wait_for_function(f"(n) => window.__userCurves.count > n && window.__brdf.pending() === 0"
                           " && !window.__brdf.url('ndf').includes('ior=1.5')", arg=n0, timeout=60_000)
    assert page.evaluate("() => window.__userCurves.evaluations") == e0

    # -- a full BRDF: the explorer's D-like slice (Walter's GGX with Smith and Fresnel)
    n = page.evaluate("() => window.__userCurves.count")
    load_brdf(page, WALTER, name="walter_ggx_dielectric.brdf")
    page.wait_for_function("() => (window.__userBrdf.source || '').includes('fresnelDielectric')", timeout=60_000)
    user = _trace(page, LABEL, n)
    page.locator("section[data-panel=ndf]").screenshot(path=str(shots / "user-dlike-walter.png"))

    # -- a Lambertian file: ρ/π at every θ_h, flat
    n = page.evaluate("() => window.__userCurves.count")
    load_brdf(page, text=LAMBERT, name="lambert.brdf")
    page.wait_for_function("() => (window.__userBrdf.source || '').includes('rho / 3.14')", timeout=60_000)
    user = _trace(page, LABEL, n)
    y = _array(user["y"])
    err = _close(y, np.full(y.size, RHO / np.pi), F32, 0.0)
    print(f"Lambertian file: {y.size} θ_h, largest relative difference from ρ/π {err:.2e}")
    assert err <= F32

    # -- Close: the trace goes, the panel's D stays
    page.click("#gpu-brdf-close")
    page.wait_for_function(f"() => !({TRACE})()", timeout=60_000)
    assert page.evaluate("() => window.__brdf.panel('ndf').figure.data.length") >= 1
    assert not page_log.problems()
