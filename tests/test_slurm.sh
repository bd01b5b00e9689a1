#!/bin/bash
# Shards on a real Slurm cluster (docs/scale-out.md): a one-node cluster
# (munged, slurmctld and slurmd as root, on private ports, socket and
# folders) runs a sharded run and a sharded tune through
# tools/slurm-submit, and what it merges equals the command unsharded,
# timings aside (same_results). A shard killed mid-way is found and
# submitted again; concurrent shards trace each ground truth once (the
# cache's per-key lock). Every daemon is stopped by its PID. Skips (77)
# only where Slurm cannot start here (not root, not installed: tools/setup
# installs it). test_shards checks merge's refusals, and check and
# stability in shards, without a scheduler.
set -u
sb=$1 same=$2
src=$(cd "$(dirname "$0")/.." && pwd)
[ "$(id -u)" = 0 ] || { echo "skipped: the test cluster's daemons run as root"; exit 77; }
for d in munged slurmctld slurmd sbatch squeue; do
  command -v $d >/dev/null || { echo "skipped: $d is not installed (tools/setup installs Slurm and munge)"; exit 77; }
done
t=$(mktemp -d /tmp/sb_test_slurm_XXXXXX)
chmod 0755 "$t"
stop_daemons() {
  for p in "$t"/slurmd.pid "$t"/slurmctld.pid "$t"/munge/munged.pid; do
    [ -s "$p" ] && kill "$(cat "$p")" 2>/dev/null
  done
  for p in "$t"/slurmd.pid "$t"/slurmctld.pid "$t"/munge/munged.pid; do
    for _ in $(seq 50); do [ -s "$p" ] && kill -0 "$(cat "$p")" 2>/dev/null || break; sleep 0.1; done
    [ -s "$p" ] && kill -KILL "$(cat "$p")" 2>/dev/null
  done
  pkill -KILL -f "$t/" 2>/dev/null
}
trap 'stop_daemons; rm -rf "$t"' EXIT
fails=0
fail() { echo "FAILED: $*"; fails=$((fails + 1)); }

# ---- the cluster: ports from this process's id, so two runs do not meet
mkdir -p "$t/munge" "$t/state" "$t/spool"
chmod 0755 "$t/munge"
head -c 1024 /dev/urandom > "$t/munge/munge.key" && chmod 0400 "$t/munge/munge.key"
port=$((20000 + ($$ % 20000)))
cat > "$t/slurm.conf" <<EOF
ClusterName=sbtest
SlurmctldHost=localhost
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
AuthInfo=socket=$t/munge/munge.socket
CredType=cred/munge
StateSaveLocation=$t/state
SlurmdSpoolDir=$t/spool
SlurmctldPidFile=$t/slurmctld.pid
SlurmdPidFile=$t/slurmd.pid
SlurmctldLogFile=$t/slurmctld.log
SlurmdLogFile=$t/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobCompType=jobcomp/filetxt
JobCompLoc=$t/jobcomp.txt
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MinJobAge=600
NodeName=localhost NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=test Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$t/slurm.conf
started() {
  munged --socket="$t/munge/munge.socket" --key-file="$t/munge/munge.key" --pid-file="$t/munge/munged.pid" \
         --log-file="$t/munge/munged.log" --seed-file="$t/munge/munged.seed" --force </dev/null >"$t/munged.out" 2>&1 &&
  slurmctld -i </dev/null >"$t/slurmctld.out" 2>&1 &&
  slurmd -N localhost </dev/null >"$t/slurmd.out" 2>&1 || return 1
  for _ in $(seq 100); do  # idle in about a second here
    sinfo -h -o %T 2>/dev/null | grep -q idle && return 0
    sleep 0.1
  done
  return 1
}
if ! started; then
  echo "skipped: Slurm did not start here:"; tail -n 3 "$t"/*.out "$t"/*.log "$t"/munge/*.log 2>/dev/null
  exit 77
fi

# ---- a sharded run, one shard killed mid-way, merged = unsharded
# Three techniques on two scenes at 96x96, at their defaults and tuned (a
# tuned cell's settings differ by scene): 2 shards of 13 cells each, and a
# ground-truth cache the shards share, empty at first.
args="--scene contact_hardening --scene sun_contact --technique hard --technique pcf --technique pcss
      --settings both --tuned $src/results/tuned --width 96 --height 96 --gt-samples 256 --frames 1"
"$sb" run $args --cache "$t/alone-cache" --out "$t/alone" >"$t/alone.log" 2>&1 || fail "the unsharded run"
# Shard 1's first try is killed once its first cell is written (a node
# lost mid-way); slurm-submit must find it unfinished and submit it again.
cat > "$t/sb-once-killed" <<EOF
#!/bin/bash
case " \$* " in *" --shard 1/2 "*)
  if mkdir "$t/killed" 2>/dev/null; then
    "$sb" "\$@" & pid=\$!
    for _ in \$(seq 1200); do compgen -G "$t/work/shard-1/*/*/metrics.json" >/dev/null && break; sleep 0.05; done
    kill -KILL \$pid; exit 137
  fi ;;
esac
exec "$sb" "\$@"
EOF
chmod +x "$t/sb-once-killed"
SHADOWBENCH="$t/sb-once-killed" "$src/tools/slurm-submit" --shards 2 --work "$t/work" --out "$t/merged" --poll 0.2 \
  -- run $args --cache "$t/shared-cache" >"$t/submit.log" 2>&1 || { fail "slurm-submit run"; cat "$t/submit.log"; }
grep -q "shard(s) 1 did not finish" "$t/submit.log" || fail "the killed shard was not found and submitted again"
[ -d "$t/killed" ] || fail "the shard was never killed"
"$same" run "$t/alone" "$t/merged" || fail "the merged run differs from the unsharded one"
grep -q '"shards"' "$t/merged/run.json" || fail "the merged run.json lists no shards"
[ -n "$(ls "$t/work/shard-1"/*/*/metrics.json 2>/dev/null)" ] || fail "the killed shard's resubmission wrote no cell"

# ---- a sharded tune, merged = unsharded (its cost counted: deterministic
# frontiers), with --write-tuned writing the tuned folder once, merged
# pcf's widest parameters held (--set), so that its search stays short
targs="--scene contact_hardening --scene parallel_planes --technique hard --technique pcf --width 96 --height 96
       --gt-samples 256 --frames 1 --cost fetches --set pcf.samples=32 --set pcf.pattern=poisson
       --set pcf.rotation=ign --set pcf.denoise_radius_px=0"
"$sb" tune $targs --cache "$t/alone-cache" --out "$t/tune-alone" >"$t/tune-alone.log" 2>&1 || fail "the unsharded tune"
"$src/tools/slurm-submit" --shards 2 --work "$t/twork" --out "$t/tune-merged" --poll 0.2 \
  -- tune $targs --cache "$t/shared-cache" --write-tuned --allow-uncommitted --tuned "$t/tuned" >"$t/tsubmit.log" 2>&1 ||
  { fail "slurm-submit tune"; cat "$t/tsubmit.log"; }
"$same" tune "$t/tune-alone" "$t/tune-merged" || fail "the merged tuning differs from the unsharded one"
"$same" tune "$t/tune-alone" "$t/tuned" || fail "the tuned folder the merge wrote differs from the unsharded tuning"
# Both tune shards need parallel_planes' truth, new to the cache, at once:
# one traces it, the other waits for it and reads it (the cache's lock).
traced=$(cat "$t"/twork/logs/*.log | grep -c 'ground truth parallel_planes: 96x96, 256 light samples')
[ "$traced" -eq 1 ] || fail "the two tune shards traced parallel_planes' ground truth $traced times, not once"

stop_daemons
for p in "$t"/slurmd.pid "$t"/slurmctld.pid "$t"/munge/munged.pid; do
  [ -s "$p" ] && kill -0 "$(cat "$p")" 2>/dev/null && fail "$(basename "$p" .pid) still runs after its stop"
done
[ $fails -eq 0 ] && echo "test_slurm: passed"
exit $((fails > 0))
