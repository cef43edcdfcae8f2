#!/usr/bin/env bash
# Submits a sharded `shadowtruth run` to Slurm: a job array of N shards, then a merge job that
# starts once every shard has succeeded (and is cancelled if one fails).
#
# Usage:
#   scripts/slurm/submit.sh -n N -o OUT [-- run arguments...]
#   e.g. scripts/slurm/submit.sh -n 8 -o reports/suite -- scenes --plan plans/bias-sweep.json
#
# The shards are written to OUT.shards/shard-K (K = 1..N), the merged report folder to OUT.
# Prints ARRAY_JOB=<id> and MERGE_JOB=<id>. Extra sbatch options (partition, account, time)
# go in $SBATCH_OPTIONS; the binary is $SHADOWTRUTH (default: `shadowtruth` on the PATH), with
# relative paths read from the directory this script is run in. See docs/cluster.md.
set -euo pipefail

usage() {
  echo "usage: $0 -n N -o OUT [-- run arguments...]" >&2
  exit 2
}
count="" out=""
while getopts "n:o:h" opt; do
  case $opt in
    n) count=$OPTARG ;;
    o) out=$OPTARG ;;
    *) usage ;;
  esac
done
shift $((OPTIND - 1))
[[ ${1:-} == "--" ]] && shift
[[ $count =~ ^[1-9][0-9]*$ && -n $out ]] || usage
case $out in *"'"*) echo "$0: OUT may not contain a single quote" >&2; exit 2 ;; esac

here=$(cd "$(dirname "$0")" && pwd)
shadowtruth=${SHADOWTRUTH:-shadowtruth}
shards_dir="$out.shards"
mkdir -p "$shards_dir"
# shellcheck disable=SC2086 # SBATCH_OPTIONS holds several options
array_job=$(SHADOWTRUTH_SHARDS=$count sbatch --parsable ${SBATCH_OPTIONS:-} --array="1-$count" \
  --output="$shards_dir/slurm-%A_%a.out" "$here/shadowtruth-array.sh" "$shards_dir" "$@")
array_job=${array_job%%;*}
# --wrap runs under /bin/sh: every path is single-quoted.
folders=""
for k in $(seq 1 "$count"); do folders="$folders '$shards_dir/shard-$k'"; done
# shellcheck disable=SC2086
merge_job=$(sbatch --parsable ${SBATCH_OPTIONS:-} --job-name=shadowtruth-merge \
  --dependency="afterok:$array_job" --kill-on-invalid-dep=yes --output="$shards_dir/slurm-merge-%j.out" \
  --wrap="exec '$shadowtruth' merge$folders -o '$out'")
merge_job=${merge_job%%;*}
echo "ARRAY_JOB=$array_job"
echo "MERGE_JOB=$merge_job"
