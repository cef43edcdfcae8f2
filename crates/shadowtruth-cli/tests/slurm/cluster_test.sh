#!/usr/bin/env bash
# Starts a real single-node Slurm cluster (munged, slurmctld, slurmd, as root, no systemd),
# submits the bundled suite as a 4-shard job array plus its merge job through
# scripts/slurm/submit.sh, and checks that the merged report folder equals an unsharded run's
# apart from timings (report.json without `created`, `bvh_build_ms` and `timings`; report.csv
# without its timing columns; the figures byte for byte; the same plots). Prints the cluster's
# wall time, then checks that a failing shard gets the merge job cancelled instead of left
# pending. scripts/test.sh runs it last, after installing munge, slurmctld, slurmd and
# slurm-client.
#
# Usage (as root): bash crates/shadowtruth-cli/tests/slurm/cluster_test.sh
#   SHADOWTRUTH=path/to/binary   default: the workspace's target/release/shadowtruth (built when
#                                missing; CARGO_TARGET_DIR is followed)
#   KEEP=1                       keep the temporary folder (config, logs, reports)
set -euo pipefail
shopt -s nullglob

# The workspace root: the bundled scenes and scripts/slurm/ are read from there.
root=$(cd "$(dirname "$0")/../../../.." && pwd)
shards=4
poll_timeout_s=180

fail() {
  echo "cluster_test: FAILED: $*" >&2
  exit 1
}
[[ $EUID -eq 0 ]] || fail "run as root: it starts munged, slurmctld and slurmd"
for cmd in munged slurmctld slurmd sbatch squeue scontrol sinfo setpriv; do
  command -v "$cmd" >/dev/null || fail "$cmd is missing (apt-get install munge slurmctld slurmd slurm-client)"
done
bin=${SHADOWTRUTH:-${CARGO_TARGET_DIR:-$root/target}/release/shadowtruth}
if [[ ! -x $bin ]]; then
  (cd "$root" && cargo build --release --locked)
fi
bin=$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")

work=$(mktemp -d /tmp/shadowtruth-slurm.XXXXXX)
chmod 755 "$work"
pids=()
show_logs() {
  for f in "$work"/logs/*.log "$work"/logs/*.out "$work"/run/merged.shards/*.out; do
    [[ -f $f ]] || continue
    echo "----- $f" >&2
    tail -n 60 "$f" >&2
  done
  [[ -z ${array_job:-} ]] || scontrol show job "$array_job" >&2 || true
  [[ -z ${merge_job:-} ]] || scontrol show job "$merge_job" >&2 || true
}
cleanup() {
  local status=$?
  if [[ $status -ne 0 ]]; then
    echo "cluster_test: exit $status; logs and job output:" >&2
    show_logs
  fi
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
    kill "${pids[i]}" 2>/dev/null || true
  done
  for pid in "${pids[@]}"; do
    wait "$pid" 2>/dev/null || true
  done
  if [[ -z ${KEEP:-} ]]; then rm -rf "$work"; else echo "kept $work" >&2; fi
  exit "$status"
}
trap cleanup EXIT

# Waits until `$@` succeeds, at most $poll_timeout_s seconds.
wait_for() {
  local what=$1
  shift
  local deadline=$((SECONDS + poll_timeout_s))
  until "$@" >/dev/null 2>&1; do
    ((SECONDS < deadline)) || fail "timed out after ${poll_timeout_s} s waiting for $what"
    sleep 0.5
  done
}

# --- munge: the key that the packages create, our own daemon, the default socket.
mkdir -p "$work/logs" "$work/state" "$work/spool" "$work/run"
chown munge: "$work/logs"
install -d -o munge -g munge -m 0755 /run/munge
[[ -s /etc/munge/munge.key ]] || { dd if=/dev/urandom bs=1 count=1024 of=/etc/munge/munge.key 2>/dev/null &&
  chown munge: /etc/munge/munge.key && chmod 400 /etc/munge/munge.key; }
if ! munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then
  setpriv --reuid=munge --regid=munge --init-groups munged --foreground --force --origin=127.0.0.1 \
    --log-file="$work/logs/munged.log" --pid-file="$work/logs/munged.pid" >>"$work/logs/munged.out" 2>&1 &
  pids+=($!)
  wait_for "munged" sh -c 'munge -n | unmunge'
fi

# --- slurm.conf: one node, this machine's hardware, no cgroups, no accounting.
hardware=$(slurmd -C | head -n 1 | sed -e 's/^NodeName=[^ ]* //' -e 's/ *$//')
export SLURM_CONF=$work/slurm.conf
cat >"$SLURM_CONF" <<CONF
ClusterName=shadowtruth-ci
SlurmctldHost=localhost(127.0.0.1)
AuthType=auth/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/logs/slurmctld.pid
SlurmdPidFile=$work/logs/slurmd.pid
SlurmctldLogFile=$work/logs/slurmctld.log
SlurmdLogFile=$work/logs/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerParameters=batch_sched_delay=0
DependencyParameters=kill_invalid_depend
ReturnToService=2
MpiDefault=none
NodeName=localhost NodeAddr=127.0.0.1 $hardware State=UNKNOWN
PartitionName=ci Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
started=$SECONDS
slurmctld -D -i -f "$SLURM_CONF" >>"$work/logs/slurmctld.out" 2>&1 &
pids+=($!)
wait_for "slurmctld" scontrol ping
slurmd -D -N localhost -f "$SLURM_CONF" >>"$work/logs/slurmd.out" 2>&1 &
pids+=($!)
wait_for "the node to be idle" sh -c '[ "$(sinfo -h -n localhost -o %t)" = idle ]'
echo "cluster up in $((SECONDS - started)) s"

# --- the suite: every bundled scene, one technique at 256², sharded and merged by Slurm.
cd "$work/run"
cat >plan.json <<'PLAN'
{ "format": "shadowtruth/plan/v1",
  "techniques": [{ "technique": "constant", "bias_depth": 0.001 }],
  "resolutions": [256], "depth_formats": ["f32"], "repeats": 1 }
PLAN
run_args=("$root/scenes" --plan plan.json --references "$work/references")
submitted_ms=$(($(date +%s%N) / 1000000))
jobs=$(SHADOWTRUTH=$bin "$root/scripts/slurm/submit.sh" -n "$shards" -o merged -- "${run_args[@]}")
array_job=$(sed -n 's/^ARRAY_JOB=//p' <<<"$jobs")
merge_job=$(sed -n 's/^MERGE_JOB=//p' <<<"$jobs")
[[ -n $array_job && -n $merge_job ]] || fail "submit.sh printed no job ids: $jobs"
job_state() { scontrol show job "$1" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p'; }
merge_finished() {
  case $(job_state "$merge_job") in
    COMPLETED) return 0 ;;
    FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY | BOOT_FAIL | DEADLINE)
      fail "merge job $merge_job ended $(job_state "$merge_job")" ;;
    *) return 1 ;;
  esac
}
deadline=$((SECONDS + poll_timeout_s))
until merge_finished; do
  ((SECONDS < deadline)) || fail "timed out after ${poll_timeout_s} s waiting for merge job $merge_job"
  sleep 0.5
done
slurm_ms=$(($(date +%s%N) / 1000000 - submitted_ms))
tasks=$(scontrol show job "$array_job" | grep -c 'JobState=COMPLETED' || true)
[[ $tasks -eq $shards ]] || fail "$tasks of $shards array tasks completed"
printf 'slurm: %d-shard array and merge finished in %d.%d s after submission\n' "$shards" \
  $((slurm_ms / 1000)) $((slurm_ms % 1000 / 100))

# --- the same plan unsharded, and the comparison.
"$bin" run "${run_args[@]}" -o whole --quiet
strip_json() { sed -e '/"created":/d' -e '/"bvh_build_ms":/d' -e '/"timings": {/,/}/d' "$1"; }
diff <(strip_json whole/report.json) <(strip_json merged/report.json) || fail "report.json differs"
# The plan's labels hold no comma, so the CSV's columns split on commas.
strip_csv() {
  awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) keep[i] = ($i !~ /^timings\./) }
           { line = ""; for (i = 1; i <= NF; i++) if (keep[i]) line = line $i ","; print line }' "$1"
}
diff <(strip_csv whole/report.csv) <(strip_csv merged/report.csv) || fail "report.csv differs"
diff <(cd whole/figures && ls) <(cd merged/figures && ls) || fail "the figures differ"
for f in whole/figures/*; do cmp "$f" "merged/figures/${f##*/}" || fail "figures/${f##*/} differs"; done
diff <(cd whole/plots && ls) <(cd merged/plots && ls) || fail "the plots differ"
for f in whole/plots/*; do
  [[ ${f##*/} == cost_* ]] || cmp "$f" "merged/plots/${f##*/}" || fail "plots/${f##*/} differs"
done
[[ -s merged/index.html ]] || fail "no merged/index.html"
# --- a failing shard: the merge's dependency can never be met, so Slurm cancels it.
jobs=$(SHADOWTRUTH=$bin "$root/scripts/slurm/submit.sh" -n 2 -o broken -- "$root/scenes" --plan missing.json)
broken_merge=$(sed -n 's/^MERGE_JOB=//p' <<<"$jobs")
merge_job=$broken_merge array_job=$(sed -n 's/^ARRAY_JOB=//p' <<<"$jobs")
merge_cancelled() {
  case $(job_state "$broken_merge") in
    CANCELLED) return 0 ;;
    COMPLETED | RUNNING) fail "the merge after a failed shard ran ($(job_state "$broken_merge"))" ;;
    *) return 1 ;;
  esac
}
deadline=$((SECONDS + poll_timeout_s))
until merge_cancelled; do
  ((SECONDS < deadline)) || fail "timed out after ${poll_timeout_s} s waiting for merge job $broken_merge to be cancelled"
  sleep 0.5
done
[[ ! -e broken ]] || fail "a merge folder was written after a failed shard"
echo "slurm: a failed shard cancels the merge job"

runs=$(($(wc -l <merged/report.csv) - 1))
figures=$(ls merged/figures | wc -l)
echo "cluster_test: passed: merged report of $shards shards equals the unsharded run ($runs runs, $figures figures)"
