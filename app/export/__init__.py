"""Exports: a view's figure as SVG/PNG (headless Chromium via kaleido), its numbers as
CSV, a standalone HTML page. Generic over :data:`app.views.VIEWS`: a view added
there is exportable with no change here."""
