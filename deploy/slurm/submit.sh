#!/usr/bin/env bash
# Submit a sharded sweep to Slurm: an array job of N shards (deploy/slurm/sweep.sbatch), then
# the merge (deploy/slurm/merge.sbatch), which starts only if every shard succeeds.
#
# Usage (from the repository root):
#   deploy/slurm/submit.sh N STUDY RESULTS_DIR
#   deploy/slurm/submit.sh N RESULTS_DIR -- SWEEP_ARGS...
#
#   e.g. deploy/slurm/submit.sh 16 studies/paper.toml results/paper
#
# Logs: RESULTS_DIR/logs/sweep-JOBID_K.out and RESULTS_DIR/logs/merge-JOBID.out.
# Merged files: RESULTS_DIR/merged/.
#
# Environment:
#   MUSE               the muse binary (default: `muse` on PATH), passed to the jobs
#   SWEEP_SBATCH_OPTS  extra sbatch options for the array job, split on spaces,
#                      e.g. "--partition=short --account=myproj --cpus-per-task=8"
#   MERGE_SBATCH_OPTS  the same for the merge job
#   (sbatch's own variables, e.g. SBATCH_ACCOUNT and SBATCH_PARTITION, apply to both)
#
# Before submitting, when `sinfo` is there, each job's CPUs and memory (the templates'
# #SBATCH defaults: 4 CPUs and 4G a shard, 1 CPU and 2G the merge; SBATCH_MEM_PER_NODE and
# SBATCH_MEM_PER_CPU; then the options above) are compared with the largest node of its
# partition (`sinfo -N -o '%c %m'`): a job no node can hold would wait forever, so it is
# refused, saying which option to set.
#
# If a shard fails, the merge is cancelled (--kill-on-invalid-dep=yes); rerun the failed
# task(s) and then submit the merge, as the script prints (with the options above).
set -euo pipefail

die() {
  printf 'submit.sh: %s\n' "$*" >&2
  exit 2
}

(($# >= 3)) || die "usage: submit.sh N STUDY RESULTS_DIR | N RESULTS_DIR -- SWEEP_ARGS..."
N=$1
shift
[[ $N =~ ^[1-9][0-9]*$ ]] || die "N must be a positive integer, not '$N'"
if [[ $2 == -- ]]; then
  RESULTS=$1
  job_args=("$@")
else
  (($# == 2)) || die "usage: submit.sh N STUDY RESULTS_DIR | N RESULTS_DIR -- SWEEP_ARGS..."
  RESULTS=$2
  job_args=("$1" "$2")
  [[ -f $1 ]] || die "study file '$1' not found (from $(pwd))"
fi
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

# Word-splitting is intended: these hold several sbatch options.
read -r -a sweep_opts <<<"${SWEEP_SBATCH_OPTS:-}"
read -r -a merge_opts <<<"${MERGE_SBATCH_OPTS:-}"

# Memory as sbatch reads it (a number of MB, or with a K, M, G or T suffix) in MB; empty
# when it is not such a number.
to_mb() {
  local v=${1^^}
  case $v in
    *K) [[ ${v%K} =~ ^[0-9]+$ ]] && echo $(((${v%K} + 1023) / 1024)) ;;
    *M) [[ ${v%M} =~ ^[0-9]+$ ]] && echo "${v%M}" ;;
    *G) [[ ${v%G} =~ ^[0-9]+$ ]] && echo $((${v%G} * 1024)) ;;
    *T) [[ ${v%T} =~ ^[0-9]+$ ]] && echo $((${v%T} * 1024 * 1024)) ;;
    *) [[ $v =~ ^[0-9]+$ ]] && echo "$v" ;;
  esac
  return 0
}

# check_fits WHO VAR TEMPLATE [OPTS...]: refuses (exit 2) a job asking for more CPUs or
# memory than the largest node of its partition has, when sinfo says. WHO names the job in
# the message, VAR the variable its options are set in.
check_fits() {
  local who=$1 var=$2 template=$3
  shift 3
  command -v sinfo >/dev/null 2>&1 || return 0
  local cpus mem mem_per_cpu="" partition=${SBATCH_PARTITION:-} cpus_given="" mem_given=""
  local kept=()
  cpus=$(sed -n 's/^#SBATCH --cpus-per-task=\([0-9]*\).*/\1/p' "$template" | head -n 1)
  mem=$(sed -n 's/^#SBATCH --mem=\([^ ]*\).*/\1/p' "$template" | head -n 1)
  [[ -n ${SBATCH_MEM_PER_NODE:-} ]] && mem=$SBATCH_MEM_PER_NODE
  [[ -n ${SBATCH_MEM_PER_CPU:-} ]] && mem="" && mem_per_cpu=$SBATCH_MEM_PER_CPU
  while (($#)); do
    case $1 in
      --cpus-per-task=*) cpus=${1#*=} cpus_given=1 ;;
      --cpus-per-task | -c) cpus=${2:-} cpus_given=1 && shift ;;
      -c?*) cpus=${1#-c} cpus_given=1 ;;
      --mem=*) mem=${1#*=} mem_per_cpu="" mem_given=1 ;;
      --mem) mem=${2:-} mem_per_cpu="" mem_given=1 && shift ;;
      --mem-per-cpu=*) mem_per_cpu=${1#*=} mem="" mem_given=1 ;;
      --mem-per-cpu) mem_per_cpu=${2:-} mem="" mem_given=1 && shift ;;
      --partition=*) partition=${1#*=} && kept+=("$1") ;;
      --partition | -p) partition=${2:-} && kept+=("$1" "${2:-}") && shift ;;
      -p?*) partition=${1#-p} && kept+=("$1") ;;
      *) kept+=("$1") ;;
    esac
    shift
  done
  [[ $cpus =~ ^[0-9]+$ ]] || cpus=1
  mem=$(to_mb "$mem")
  if [[ -n $mem_per_cpu ]]; then
    mem=$(to_mb "$mem_per_cpu")
    [[ -n $mem ]] && mem=$((mem * cpus))
  fi
  [[ $mem == 0 ]] && mem="" # --mem=0: all of a node's memory
  local nodes max_cpus=0 max_mem=0 fits="" c m
  nodes=$(sinfo -h -N ${partition:+-p "$partition"} -o '%c %m' 2>/dev/null) || return 0
  while read -r c m; do
    c=${c//[^0-9]/} m=${m//[^0-9]/}
    [[ -n $c && -n $m ]] || continue
    ((c > max_cpus)) && max_cpus=$c
    ((m > max_mem)) && max_mem=$m
    ((cpus <= c)) && [[ -z $mem || $mem -le $m ]] && fits=1
  done <<<"$nodes"
  ((max_cpus > 0)) && [[ -z $fits ]] || return 0
  local asks=() has=() set=("${kept[@]+"${kept[@]}"}")
  if ((cpus > max_cpus)); then
    asks+=("$cpus CPUs (--cpus-per-task)") && has+=("$max_cpus CPUs")
    set+=("--cpus-per-task=$max_cpus")
  elif [[ -n $cpus_given ]]; then
    set+=("--cpus-per-task=$cpus")
  fi
  if [[ -n $mem ]] && ((mem > max_mem)); then
    asks+=("$mem MB of memory (--mem)") && has+=("$max_mem MB")
    set+=("--mem=${max_mem}M")
  elif [[ -n $mem_given ]]; then
    set+=("--mem=${mem}M")
  fi
  local verb="ask" they="they"
  [[ $who == *job ]] && verb="asks" they="it"
  if ((${#asks[@]} == 0)); then
    die "$who $verb for $cpus CPUs and $mem MB, but no node has both (sinfo): $they would" \
      "wait forever; set $var with fewer --cpus-per-task or less --mem"
  fi
  local IFS=' '
  local and_asks=${asks[*]} and_has=${has[*]}
  ((${#asks[@]} == 2)) && and_asks="${asks[0]} and ${asks[1]}" && and_has="${has[0]} and ${has[1]}"
  die "$who $verb for $and_asks, but the largest node has $and_has (sinfo): $they would" \
    "wait forever; set $var=\"${set[*]}\""
}

check_fits "the sweep's tasks" SWEEP_SBATCH_OPTS "$here/sweep.sbatch" ${sweep_opts[@]+"${sweep_opts[@]}"}
check_fits "the merge job" MERGE_SBATCH_OPTS "$here/merge.sbatch" ${merge_opts[@]+"${merge_opts[@]}"}

mkdir -p "$RESULTS/logs" # Slurm does not create the folders of --output

# --parsable prints "jobid" or "jobid;cluster". (The ${a[@]+...} form: empty arrays under
# set -u in bash < 4.4.)
array_id=$(sbatch --parsable --array="0-$((N - 1))" --export="ALL,SHARDS=$N" \
  --output="$RESULTS/logs/sweep-%A_%a.out" ${sweep_opts[@]+"${sweep_opts[@]}"} \
  "$here/sweep.sbatch" "${job_args[@]}")
array_id=${array_id%%;*}
merge_id=$(sbatch --parsable --dependency="afterok:$array_id" --kill-on-invalid-dep=yes \
  --output="$RESULTS/logs/merge-%j.out" ${merge_opts[@]+"${merge_opts[@]}"} \
  "$here/merge.sbatch" "$RESULTS")
merge_id=${merge_id%%;*}

# The options the jobs were submitted with, so that a rerun asks for what the first run did.
rerun=(sbatch --array=K ${sweep_opts[@]+"${sweep_opts[@]}"} --output="$RESULTS/logs/sweep-%A_%a.out"
  "$here/sweep.sbatch" "${job_args[@]}")
remerge=(sbatch --dependency=afterok:RERUN_JOB_ID ${merge_opts[@]+"${merge_opts[@]}"}
  --output="$RESULTS/logs/merge-%j.out" "$here/merge.sbatch" "$RESULTS")
printf 'sweep array job: %s (%d shards, tasks 0-%d)\n' "$array_id" "$N" "$((N - 1))"
printf 'merge job:       %s (after every shard succeeds)\n' "$merge_id"
printf 'watch:           squeue -j %s,%s\n' "$array_id" "$merge_id"
printf 'rerun task(s) K: SHARDS=%d' "$N"
printf ' %q' "${rerun[@]}"
printf '\nthen merge:     '
printf ' %q' "${remerge[@]}"
printf '\n'
