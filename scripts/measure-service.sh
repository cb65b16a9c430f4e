#!/usr/bin/env bash
# Measures `muse serve` as the README reports it, for one or more builds in the same run:
#   - `muse load` closed loop (16 clients, 20 s) and paced (2,000 requests/s by 16 clients, 20 s)
#     against a fresh data folder;
#   - restart: a service is filled with N stored flights (0.1 M, 1 M, 2 M by default, closed
#     loop, Singapore uniform demand departing within a day), killed with SIGKILL and started
#     again on the same folder; the time from the start to "listening on" (every route
#     answers) and the peak resident memory of the restarted process (VmHWM) are recorded,
#     then again with the service clock two days later (every stored flight has ended).
#
# Usage: scripts/measure-service.sh OUT_DIR LABEL=BINARY [LABEL=BINARY ...]
#   e.g. scripts/measure-service.sh out/service new=target/release/muse old=/tmp/old/muse
# Environment: SIZES (default "100000 1000000 2000000"), DURATION (default 20),
#   LOAD (the `muse` binary whose `muse load` drives every service; default the first one).
# Loopback only; every process it starts is stopped by its own id. Writes OUT_DIR/*.json,
# OUT_DIR/*.log and OUT_DIR/summary.tsv.
set -euo pipefail

out=${1:?usage: measure-service.sh OUT_DIR LABEL=BINARY ...}
shift
(($# > 0)) || { echo "error: give at least one LABEL=BINARY" >&2; exit 2; }
sizes=${SIZES:-100000 1000000 2000000}
duration=${DURATION:-20}
mkdir -p "$out"
first_bin=${1#*=}
load_bin=${LOAD:-$first_bin}
summary="$out/summary.tsv"
printf 'build\tmeasure\tvalue\n' >"$summary"

pid=""
cleanup() { [[ -n "$pid" ]] && kill -KILL "$pid" 2>/dev/null || true; }
trap cleanup EXIT

# start BIN DATA LOG [ARGS...]: starts `muse serve` on a free port; sets pid, url, start_s,
# ready_s.
start() {
  local bin=$1 data=$2 log=$3
  shift 3
  start_s=$(date +%s.%N)
  "$bin" serve --listen 127.0.0.1:0 --data "$data" --rate-limit 0 "$@" >"$log" 2>&1 &
  pid=$!
  url=""
  for _ in $(seq 1 36000); do
    if grep -q '^listening on ' "$log"; then
      url=$(sed -n 's/^listening on //p' "$log" | head -n1)
      break
    fi
    kill -0 "$pid" 2>/dev/null || { echo "error: muse serve exited: $(cat "$log")" >&2; exit 1; }
    sleep 0.01
  done
  [[ -n "$url" ]] || { echo "error: muse serve did not start" >&2; exit 1; }
  ready_s=$(date +%s.%N)
}

kill9() { kill -KILL "$pid"; wait "$pid" 2>/dev/null || true; pid=""; }

record() { printf '%s\t%s\t%s\n' "$1" "$2" "$3" | tee -a "$summary"; }

for spec in "$@"; do
  label=${spec%%=*}
  bin=${spec#*=}
  [[ -x "$bin" ]] || { echo "error: $bin is not an executable" >&2; exit 2; }

  # Load: closed loop, then paced, each against a fresh folder.
  for mode in closed paced; do
    data=$(mktemp -d)
    start "$bin" "$data" "$out/$label-$mode-serve.log"
    args=(--clients 16 --duration "$duration")
    [[ $mode == paced ]] && args+=(--rate 2000)
    "$load_bin" load --url "$url" "${args[@]}" --out "$out/$label-$mode.json" \
      >"$out/$label-$mode.log" 2>&1
    record "$label" "load $mode" "$(tail -n 20 "$out/$label-$mode.log" | tr '\n' ' ')"
    kill9
    rm -rf "$data"
  done

  # Restart with N stored flights.
  data=$(mktemp -d)
  stored=0
  start "$bin" "$data" "$out/$label-fill.log"
  for n in $sizes; do
    more=$((n - stored))
    "$load_bin" load --url "$url" --clients 16 --count "$more" --no-verify \
      --id-prefix "fill$n-" --out "$out/$label-fill-$n.json" >"$out/$label-fill-$n.log" 2>&1
    stored=$n
    kill9
    start "$bin" "$data" "$out/$label-restart-$n.log"
    secs=$(echo "$ready_s - $start_s" | bc)
    hwm=$(awk '/VmHWM/ {print $2, $3}' "/proc/$pid/status")
    record "$label" "restart at $n stored: seconds to listening" "$secs"
    record "$label" "restart at $n stored: peak resident memory" "$hwm"
    record "$label" "store size at $n" "$(du -sh "$data" | cut -f1)"
    kill9
    start "$bin" "$data" "$out/$label-restart-later-$n.log" --clock "$(date -d '+2 days' --iso-8601=seconds)"
    secs=$(echo "$ready_s - $start_s" | bc)
    hwm=$(awk '/VmHWM/ {print $2, $3}' "/proc/$pid/status")
    record "$label" "restart at $n stored, clock 2 days later: seconds to listening" "$secs"
    record "$label" "restart at $n stored, clock 2 days later: peak resident memory" "$hwm"
    kill9
    start "$bin" "$data" "$out/$label-fill.log"
  done
  kill9
  rm -rf "$data"
done
echo "wrote $summary"
