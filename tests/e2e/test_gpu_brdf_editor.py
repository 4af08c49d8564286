"""The .brdf editor (static/js/gpu/editor.js): an opened file's text in a textarea,
recompiled and redrawn as the user types; a broken text names its line and leaves the
last good BRDF drawn; the edited BRDF is what is measured and what the link keeps.

References: scaling f by 2 (an exact float operation) doubles the sphere's radiance
and the albedo exactly; the error's line is counted here in the text typed.
"""
from __future__ import annotations

import pytest

from tests.e2e.user_brdf_page import LOADED, WALTER, load_brdf, open_gpu_page

pytestmark = pytest.mark.e2e

EDITOR = "#gpu-brdf-editor"


def _caret_at(page, needle: str):
    """The caret placed where `needle` (once in the text) starts, as a click there would."""
    assert page.input_value(EDITOR).count(needle) == 1, needle
    page.evaluate("""(n) => { const a = document.getElementById('gpu-brdf-editor');
                     const i = a.value.indexOf(n); a.focus(); a.setSelectionRange(i, i); }""", needle)


def _settled(page):
    """Waits until what the editor shows answers its text as typed (the debounce after the
    last keystroke, then the compile): a half-typed state compiled on the way is passed."""
    page.wait_for_function("() => window.__userBrdf.settled", timeout=30_000)


def test_typing_redraws_errors_name_their_line_and_the_link_keeps_the_edit(page, page_log, context, shots):
    open_gpu_page(page)
    page.click("#gpu-brdf-write")
    assert page.is_visible(EDITOR) and page.evaluate("() => document.activeElement.id") == "gpu-brdf-editor"
    assert "::begin shader" in page.input_value(EDITOR)           # the template before any file
    load_brdf(page, WALTER, name="walter.brdf")
    page.wait_for_function(LOADED, timeout=60_000)
    assert page.input_value(EDITOR) == WALTER.read_text()          # the opened file's text
    page.wait_for_function("() => /[?&]ubrdf=/.test(location.search)", timeout=30_000)
    first = page.evaluate("() => new URLSearchParams(location.search).get('ubrdf')")
    before = page.evaluate("() => window.__userBrdf.sphere()")
    measured = page.evaluate("() => window.__userBrdf.measure()")

    # scale f by 2, typed
    _caret_at(page, "vec3(D * G * F")
    page.keyboard.type("2 * ")
    _settled(page)
    assert "return 2 * vec3(" in page.evaluate("() => window.__userBrdf.source")
    doubled = page.evaluate("() => window.__userBrdf.sphere()")
    assert doubled["total"] == pytest.approx(2 * before["total"], rel=1e-12)
    again = page.evaluate("() => window.__userBrdf.measure()")
    for a, b in zip(again["albedo"], measured["albedo"]):
        assert a["E"][0] == pytest.approx(2 * b["E"][0], rel=1e-12)
    assert page.is_hidden("#gpu-editor-message")
    assert "walter.brdf (edited)" in page.text_content("#gpu-brdf-message")

    # a syntax error: its line, counted in the text typed, in the message and the gutter
    _caret_at(page, ";\n}\n::end shader")
    page.keyboard.type(" +")
    _settled(page)
    typed = page.input_value(EDITOR).split("\n")
    line = next(i for i, x in enumerate(typed, 1) if "NdotV)) +;" in x)
    message = page.text_content("#gpu-editor-message")
    assert f"line {line}:" in message and "does not compile" in message, message
    assert page.text_content(".gpu-editor-bad") == str(line)
    assert page.evaluate("() => window.__userBrdf.sphere()")["total"] == doubled["total"]   # still drawn
    assert "return 2 * vec3(" in page.evaluate("() => window.__userBrdf.source")
    page.locator("#panel-gpu").screenshot(path=str(shots / "gpu-brdf-editor-error.png"))

    # fixed: the message and the mark go
    page.keyboard.press("Backspace")
    page.keyboard.press("Backspace")
    _settled(page)
    assert page.is_hidden("#gpu-editor-message") and page.locator(".gpu-editor-bad").count() == 0

    # a parameter line that does not parse: its line too, then fixed
    _caret_at(page, "float eta ")
    page.keyboard.type("x")
    _settled(page)
    line = next(i for i, x in enumerate(page.input_value(EDITOR).split("\n"), 1) if x.startswith("xfloat eta"))
    assert f"line {line}:" in page.text_content("#gpu-editor-message")
    assert page.text_content(".gpu-editor-bad") == str(line)
    page.keyboard.press("Backspace")
    _settled(page)
    assert page.is_hidden("#gpu-editor-message")

    # a slider's value survives an edit of the shader, not one of its own declaration
    page.evaluate("() => window.__userBrdf.setValue('alpha', 0.45)")
    _caret_at(page, "float D = GGX_D")
    page.keyboard.type(" ")
    _settled(page)
    assert page.evaluate("() => window.__userBrdf.values.alpha") == pytest.approx(0.45)
    _caret_at(page, " 0.3\n")
    page.keyboard.press("Delete")
    page.keyboard.press("Delete")
    page.keyboard.press("Delete")
    page.keyboard.press("Delete")
    page.keyboard.type(" 0.2")
    _settled(page)
    assert page.evaluate("() => window.__userBrdf.values.alpha") == pytest.approx(0.2)

    # the link keeps the edited text: another page opens it
    page.wait_for_function("(f) => new URLSearchParams(location.search).get('ubrdf') !== f", arg=first, timeout=30_000)
    other = context.new_page()
    other.goto(page.url)
    other.wait_for_function(LOADED, timeout=60_000)
    assert "return 2 * vec3(" in other.evaluate("() => window.__userBrdf.source")
    assert "return 2 * vec3(" in other.input_value(EDITOR)

    # a file that does not compile opens in the editor with its line marked, to be fixed
    broken = WALTER.read_text().replace("float D = GGX_D(dot(N, H), alpha);", "float D = GGX_D(dot(N, H), alpha)")
    load_brdf(page, name="broken.brdf", text=broken)
    page.wait_for_function("() => /broken\\.brdf: the shader does not compile/.test(window.__userBrdf.message)", timeout=30_000)
    assert page.input_value(EDITOR) == broken
    line = next(i for i, x in enumerate(broken.split("\n"), 1) if x.endswith("GGX_D(dot(N, H), alpha)")) + 1
    assert f"line {line}:" in page.text_content("#gpu-editor-message")            # the missing ';' is seen on the next line
    assert page.text_content(".gpu-editor-bad") == str(line)
    _caret_at(page, "alpha)\n    float G")
    page.keyboard.press("End")
    page.keyboard.type(";")
    _settled(page)
    assert page.is_hidden("#gpu-editor-message")
    assert page.text_content("#gpu-brdf-message").startswith("broken.brdf (edited): 3 parameters")
    assert not page_log.problems()
