// Runs in <head>, before first paint, so ?embed=1 never flashes the controls. An
// external file (not an inline <script>) so that a strict Content-Security-Policy
// (script-src 'self') allows it.
"use strict";
if (new URLSearchParams(location.search).get("embed") === "1") {
  document.documentElement.classList.add("embed");
}
