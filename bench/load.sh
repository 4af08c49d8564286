#!/usr/bin/env bash
# Load: wrk against 127.0.0.1 with 1 and 2 uvicorn workers, the requests of a slider drag.
#
#   bench/load.sh                         # 10 s per run, 8 connections, workers 1 then 2
#   DURATION=3s WORKERS="1" bench/load.sh # shorter (what a CI smoke run would use)
#
# Each run starts `brdf-explorer serve --workers N --port $PORT` on 127.0.0.1 only,
# waits for /api/v1/health, warms each worker up (imports, first figures), runs wrk with
# bench/load.lua (lobe, ndf, g1 and albedo figures, α stepping as a user drags the
# slider, nothing served from the albedo cache), prints requests/s, p50, p99 and the
# error count (non-2xx, socket errors, timeouts), and stops the server. Exits non-zero
# when any request failed. Not part of the test suite: it measures, it does not check
# a speed goal. Needs wrk (apt-get install -y wrk).
set -euo pipefail
cd "$(dirname "$0")/.."

DURATION=${DURATION:-10s}
CONNECTIONS=${CONNECTIONS:-8}
THREADS=${THREADS:-2}
PORT=${PORT:-8010}
WORKERS=${WORKERS:-"1 2"}
TIMEOUT=${TIMEOUT:-30s}            # wrk's default (2 s) would count a queued albedo as an error
URL="http://127.0.0.1:${PORT}"

command -v wrk >/dev/null || { echo "wrk is not installed: apt-get install -y wrk" >&2; exit 2; }
command -v brdf-explorer >/dev/null || { echo "run 'pip install -e .' first" >&2; exit 2; }

server=""
stop() {
  if [[ -n "$server" ]] && kill -0 "$server" 2>/dev/null; then
    kill -TERM "$server"; wait "$server" 2>/dev/null || true
  fi
  server=""
}
trap stop EXIT

failed=0
echo "# $(date -u +%FT%TZ)  $(nproc) cores  load average: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# wrk -t$THREADS -c$CONNECTIONS -d$DURATION --timeout $TIMEOUT, bench/load.lua"
for n in $WORKERS; do
  brdf-explorer serve --host 127.0.0.1 --port "$PORT" --workers "$n" >"/tmp/brdf-load-$n.log" 2>&1 &
  server=$!
  for _ in $(seq 150); do
    curl -fs "$URL/api/v1/health" >/dev/null 2>&1 && break
    sleep 0.2
  done
  curl -fs "$URL/api/v1/health" >/dev/null || { echo "server did not start"; cat "/tmp/brdf-load-$n.log"; exit 1; }
  # every worker imports and draws once before the clock starts
  for _ in $(seq $((4 * n))); do
    for p in "lobe?theta_i_deg=45&" "ndf?" "g1?" "albedo?"; do
      curl -fs -o /dev/null "$URL/api/v1/figures/${p}alpha=0.3" &
    done
  done
  wait $(jobs -p | grep -v "^$server\$") 2>/dev/null || true
  result=$(wrk -t"$THREADS" -c"$CONNECTIONS" -d"$DURATION" --timeout "$TIMEOUT" -s bench/load.lua "$URL" \
           | grep '^RESULT')
  echo "workers=$n ${result#RESULT }"
  [[ "$result" =~ errors=0\  ]] || failed=1
  stop
done
exit "$failed"
