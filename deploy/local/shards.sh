#!/usr/bin/env bash
# Run one sweep as N shards in N separate processes on this machine, at most P at a time,
# then merge them; print the wall time of each shard, of the shards together, of the merge
# and of the whole.
#
# Usage:
#   deploy/local/shards.sh N P OUT -- SWEEP_ARGS...
#
#   deploy/local/shards.sh 8 2 out/paper-8x2 -- --study studies/paper.toml
#   MUSE=target/release/muse THREADS=1 deploy/local/shards.sh 4 2 /tmp/s -- --counts 100,200 --reps 2
#
#   N            number of shards (shard K of N runs the runs K, K+N, ... of the sweep)
#   P            how many shards run at the same time
#   OUT          output folder: OUT/shard-K/shard.json, OUT/shard-K.log (each shard's output),
#                OUT/merged/ (sweep.csv, sweep_summary.csv, plots), OUT/merge.log,
#                OUT/times.tsv (shard, start, end, seconds, exit status)
#   SWEEP_ARGS   passed verbatim to `muse sweep` (must not contain --shard, --out, --threads)
#
# Environment:
#   MUSE     the muse binary (default: `muse` on PATH)
#   THREADS  worker threads per shard (default: the cores `nproc` reports divided by P, at least 1)
#
# Exits non-zero, without merging, if any shard fails; shards not yet started are then not
# started. Run it from the folder the sweep's relative paths are relative to (the repository
# root): the merge re-reads the sweep's input files from there. Needs bash >= 4.3.
set -euo pipefail
export LC_ALL=C # a '.' decimal point in $EPOCHREALTIME and awk

usage() {
  sed -n '/^# Usage:/,/^set -euo pipefail/p' "$0" | sed '$d; s/^# \{0,1\}//' >&2
  exit 2
}
die() {
  printf 'shards.sh: %s\n' "$*" >&2
  exit 2
}

(($# >= 4)) || usage
N=$1 P=$2 OUT=$3
[[ $4 == -- ]] || usage
shift 4
SWEEP_ARGS=("$@")
MUSE=${MUSE:-muse}

[[ $N =~ ^[1-9][0-9]*$ ]] || die "N must be a positive integer, not '$N'"
[[ $P =~ ^[1-9][0-9]*$ ]] || die "P must be a positive integer, not '$P'"
[[ -n $OUT ]] || die "OUT must not be empty"
for arg in "${SWEEP_ARGS[@]}"; do
  case $arg in
  --shard | --shard=* | --out | --out=* | --threads | --threads=*)
    die "the script sets $arg itself (THREADS=... for --threads); remove it from SWEEP_ARGS"
    ;;
  esac
done
[[ ${SWEEP_ARGS[0]:-} != merge ]] || die "SWEEP_ARGS are the flags of 'muse sweep', not 'merge'"
command -v "$MUSE" >/dev/null 2>&1 || die "muse binary '$MUSE' not found (set MUSE=path/to/muse)"
if [[ -z ${THREADS:-} ]]; then
  THREADS=$(($(nproc) / P))
  ((THREADS >= 1)) || THREADS=1
fi
[[ $THREADS =~ ^[1-9][0-9]*$ ]] || die "THREADS must be a positive integer, not '$THREADS'"

now() {
  if [[ -n ${EPOCHREALTIME:-} ]]; then
    printf '%s\n' "$EPOCHREALTIME"
  else
    date +%s.%N
  fi
}
secs() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", b - a }'; }

mkdir -p "$OUT"
STATUS=$(mktemp -d "${TMPDIR:-/tmp}/muse-shards.XXXXXX")
declare -a PIDS=()

# On any exit: stop the shards still running (their subshells forward the signal to muse)
# and remove the status folder. Background jobs of a script ignore SIGINT, hence the TERM.
cleanup() {
  local pid
  for pid in "${PIDS[@]}"; do
    kill -TERM "$pid" 2>/dev/null || true
  done
  wait 2>/dev/null || true
  rm -rf "$STATUS"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# One shard; called with `&`, so it runs in its own background subshell (whose pid is the one
# in PIDS). Runs muse in the background so that a TERM can be forwarded to it, and records
# "K start end exit-status" in $STATUS/K.
run_shard() {
  local k=$1 start end rc=0 child
  # TERM from cleanup, or INT from a Ctrl-C to the whole process group (which would otherwise
  # run the main shell's INT trap here): stop muse, then record its exit as usual.
  trap '[[ -n ${child:-} ]] && kill -TERM "$child" 2>/dev/null' TERM INT
  start=$(now)
  "$MUSE" sweep "${SWEEP_ARGS[@]}" --shard "$k/$N" --threads "$THREADS" \
    --out "$OUT/shard-$k" >"$OUT/shard-$k.log" 2>&1 </dev/null &
  child=$!
  wait "$child" || rc=$?
  # A forwarded TERM interrupts the first wait: wait for muse itself to exit.
  while kill -0 "$child" 2>/dev/null; do
    rc=0
    wait "$child" || rc=$?
  done
  end=$(now)
  printf '%s %s %s %s\n' "$k" "$start" "$end" "$rc" >"$STATUS/$k.tmp"
  mv "$STATUS/$k.tmp" "$STATUS/$k"
  return "$rc"
}

failed() {
  local f rc
  for f in "$STATUS"/*; do
    [[ -f $f && $f != *.tmp ]] || continue
    read -r _ _ _ rc <"$f"
    ((rc == 0)) || return 0
  done
  return 1
}

printf 'shards.sh: %d shard(s), %d at a time, %d thread(s) each, into %s\n' \
  "$N" "$P" "$THREADS" "$OUT"
printf 'shards.sh: %s sweep %s --shard K/%d --threads %d --out %s/shard-K\n' \
  "$MUSE" "${SWEEP_ARGS[*]}" "$N" "$THREADS" "$OUT"

T0=$(now)
running=0
launched=0
for ((k = 0; k < N; k++)); do
  if ((running >= P)); then
    wait -n || true
    running=$((running - 1))
  fi
  failed && break
  run_shard "$k" &
  PIDS+=("$!")
  running=$((running + 1))
  launched=$((launched + 1))
done
wait || true
PIDS=()
T1=$(now)

# Report every shard, in order.
printf 'shard\tstart\tend\tseconds\texit\n' >"$OUT/times.tsv"
bad=()
for ((k = 0; k < N; k++)); do
  if [[ ! -f $STATUS/$k ]]; then
    if ((k < launched)); then
      bad+=("$k")
      printf 'shard %d/%d: FAILED (no exit status recorded); see %s\n' "$k" "$N" "$OUT/shard-$k.log"
    else
      printf 'shard %d/%d: not run\n' "$k" "$N"
    fi
    continue
  fi
  read -r _ start end rc <"$STATUS/$k"
  printf '%d\t%s\t%s\t%s\t%d\n' "$k" "$start" "$end" "$(secs "$start" "$end")" "$rc" >>"$OUT/times.tsv"
  if ((rc == 0)); then
    printf 'shard %d/%d: %s s\n' "$k" "$N" "$(secs "$start" "$end")"
  else
    bad+=("$k")
    printf 'shard %d/%d: FAILED (exit %d) after %s s; see %s\n' \
      "$k" "$N" "$rc" "$(secs "$start" "$end")" "$OUT/shard-$k.log"
  fi
done
if ((${#bad[@]} > 0 || launched < N)); then
  printf 'shards.sh: failed shard(s): %s; not merging. Last lines of the first failure:\n' \
    "${bad[*]:-?}" >&2
  [[ ${#bad[@]} -gt 0 ]] && tail -n 5 "$OUT/shard-${bad[0]}.log" >&2
  exit 1
fi
printf 'shards: %s s wall (%d shards, %d at a time)\n' "$(secs "$T0" "$T1")" "$N" "$P"

# Merge exactly shard-0 .. shard-(N-1) (not a glob: stale folders of another N stay out).
dirs=()
for ((k = 0; k < N; k++)); do dirs+=("$OUT/shard-$k"); done
T2=$(now)
rc=0
"$MUSE" sweep merge "${dirs[@]}" --out "$OUT/merged" >"$OUT/merge.log" 2>&1 </dev/null || rc=$?
if ((rc != 0)); then
  printf 'shards.sh: merge failed (exit %d); see %s:\n' "$rc" "$OUT/merge.log" >&2
  tail -n 5 "$OUT/merge.log" >&2
  exit 1
fi
T3=$(now)
cat "$OUT/merge.log"
printf 'merge: %s s wall\n' "$(secs "$T2" "$T3")"
printf 'total: %s s wall (shards and merge)\n' "$(secs "$T0" "$T3")"
