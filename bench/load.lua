-- wrk script for bench/load.sh: what the page asks for on a slider move.
--
-- Each request is one panel of one slider position: the four panels shown by default
-- (lobe, ndf, g1, albedo figures), α stepping through a fine grid as a user drags it,
-- each wrk thread on its own stretch of the grid. Positions are not revisited within a
-- run of ALPHA_STEPS × 4 requests per thread, so every albedo is computed, not served
-- from the server's cache: the cost of a real slider drag, not of a replay.

local PANELS = {"lobe?theta_i_deg=45&", "ndf?", "g1?", "albedo?"}
local ALPHA_STEPS = 20000          -- α = 0.01 .. 0.99 in this many steps
local counter = 0

function setup(thread)
  thread:set("id", counter)
  counter = counter + 1
end

function init(args)
  step = (tonumber(id) or 0) * 5000   -- threads start far apart on the grid
  panel = 0
end

function request()
  panel = panel % #PANELS + 1
  if panel == 1 then step = step + 1 end
  local alpha = 0.01 + 0.98 * ((step % ALPHA_STEPS) / ALPHA_STEPS)
  return wrk.format("GET", string.format("/api/v1/figures/%sndf=ggx&alpha=%.5f", PANELS[panel], alpha))
end

function done(summary, latency, requests)
  local e = summary.errors
  local errors = e.connect + e.read + e.write + e.status + e.timeout
  io.write(string.format(
    "RESULT requests=%d seconds=%.2f rps=%.1f p50_ms=%.1f p99_ms=%.1f max_ms=%.1f errors=%d (status %d, timeout %d)\n",
    summary.requests, summary.duration / 1e6, summary.requests / (summary.duration / 1e6),
    latency:percentile(50) / 1000, latency:percentile(99) / 1000, latency.max / 1000,
    errors, e.status, e.timeout))
end
