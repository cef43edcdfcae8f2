#!/usr/bin/env bash
# One shard of a `shadowtruth run`, as one task of a Slurm job array.
#
# Usage:
#   sbatch --array=1-N scripts/slurm/shadowtruth-array.sh SHARDS_DIR [run arguments...]
#
# Task K writes SHARDS_DIR/shard-K with `shadowtruth run ... --shard K/N --resume`, N being the
# array's highest task id (or $SHADOWTRUTH_SHARDS). --resume makes a requeued or restarted task
# finish its folder instead of starting over. The script adds --shard, --resume, --quiet,
# --threads ($SLURM_CPUS_PER_TASK) and -o: pass the scenes, the plan and other options only. Merge the N folders afterwards with
# `shadowtruth merge SHARDS_DIR/shard-* -o OUT` (scripts/slurm/submit.sh submits both; see
# docs/cluster.md). The binary is $SHADOWTRUTH (default: `shadowtruth` on the PATH).
#SBATCH --job-name=shadowtruth-shard
#SBATCH --cpus-per-task=1
set -euo pipefail

: "${SLURM_ARRAY_TASK_ID:?submit with sbatch --array=1-N (one task per shard)}"
if [[ $# -lt 1 ]]; then
  echo "usage: sbatch --array=1-N $0 SHARDS_DIR [run arguments...]" >&2
  exit 2
fi
shards_dir=$1
shift
count=${SHADOWTRUTH_SHARDS:-${SLURM_ARRAY_TASK_MAX:?}}
index=$SLURM_ARRAY_TASK_ID
mkdir -p "$shards_dir"
exec "${SHADOWTRUTH:-shadowtruth}" run "$@" --shard "$index/$count" --resume --quiet \
  --threads "${SLURM_CPUS_PER_TASK:-1}" -o "$shards_dir/shard-$index"
