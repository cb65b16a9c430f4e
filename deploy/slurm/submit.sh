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
# If a shard fails, the merge is cancelled (--kill-on-invalid-dep=yes); rerun the failed
# task(s) and then submit the merge, as the script prints.
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
mkdir -p "$RESULTS/logs" # Slurm does not create the folders of --output

# Word-splitting is intended: these hold several sbatch options.
read -r -a sweep_opts <<<"${SWEEP_SBATCH_OPTS:-}"
read -r -a merge_opts <<<"${MERGE_SBATCH_OPTS:-}"

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

rerun=(sbatch --array=K --output="$RESULTS/logs/sweep-%A_%a.out" "$here/sweep.sbatch" "${job_args[@]}")
remerge=(sbatch --dependency=afterok:RERUN_JOB_ID --output="$RESULTS/logs/merge-%j.out" "$here/merge.sbatch" "$RESULTS")
printf 'sweep array job: %s (%d shards, tasks 0-%d)\n' "$array_id" "$N" "$((N - 1))"
printf 'merge job:       %s (after every shard succeeds)\n' "$merge_id"
printf 'watch:           squeue -j %s,%s\n' "$array_id" "$merge_id"
printf 'rerun task(s) K: SHARDS=%d' "$N"
printf ' %q' "${rerun[@]}"
printf '\nthen merge:     '
printf ' %q' "${remerge[@]}"
printf '\n'
