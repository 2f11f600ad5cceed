#!/usr/bin/env bash
# A one-node Slurm cluster on localhost for the test of tools/slurm-sweep.sh: starts munged, slurmctld
# and slurmd from a private configuration in a temporary directory (own ports, state, sockets), submits
# a small sweep as an array of shards plus the dependent merge, waits for them, and checks that the
# merged CSV equals the same grid run in one process (timing columns aside). Stops every daemon it
# started on exit. Needs root (the daemons run as root) and Debian's slurm-wlm and munge
# (tools/install-deps.sh). Usage: tools/test_slurm_sweep.sh PATH-TO-SDFBRICK
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$(realpath "$1")
for tool in munged mungekey slurmctld slurmd sbatch squeue sinfo; do
    command -v "$tool" > /dev/null || { echo "FAIL: $tool not found (tools/install-deps.sh installs slurm-wlm and munge)"; exit 1; }
done
root=()  # the daemons run as root: directly, or through sudo
if [[ $(id -u) -ne 0 ]]; then
    sudo -n true 2> /dev/null || { echo "FAIL: the test starts Slurm's daemons: run it as root or with sudo"; exit 1; }
    root=(sudo -n)
fi

tmp=$(mktemp -d /tmp/sdfbrick-slurm.XXXXXX)
chmod 755 "$tmp"
pids=()
cleanup() {
    for pid in "${pids[@]+"${pids[@]}"}"; do "${root[@]+"${root[@]}"}" kill "$pid" 2> /dev/null || true; done
    for pid in "${pids[@]+"${pids[@]}"}"; do wait "$pid" 2> /dev/null || true; done
    "${root[@]+"${root[@]}"}" rm -rf "$tmp"
}
trap cleanup EXIT
as_root() { "${root[@]+"${root[@]}"}" "$@"; }
node=$(hostname -s)
port=$((20000 + RANDOM % 20000))

# munge: a fresh key and a private socket.
as_root mkdir -m 755 "$tmp/munge"
as_root mungekey --create --keyfile="$tmp/munge/munge.key" 2> /dev/null 
as_root chmod 400 "$tmp/munge/munge.key"
"${root[@]+"${root[@]}"}" munged --foreground --force --key-file="$tmp/munge/munge.key" --socket="$tmp/munge/socket" \
    --pid-file="$tmp/munge/pid" --log-file="$tmp/munge/log" --seed-file="$tmp/munge/seed" > "$tmp/munged.out" 2>&1 &
pids+=($!)

mkdir -p "$tmp/state" "$tmp/spool" "$tmp/out"
cat > "$tmp/slurm.conf" << EOF
ClusterName=sdfbrick-test
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$tmp/munge/socket
CredType=cred/munge
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/slurmctld.log
SlurmdLogFile=$tmp/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
NodeName=$node NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$tmp/slurm.conf
for ((i = 0; i < 50; ++i)); do as_root test -S "$tmp/munge/socket" && break; sleep 0.1; done
# Started directly (not through a shell function), so that $! is the daemon (or sudo) itself.
"${root[@]+"${root[@]}"}" slurmctld -D -i -f "$SLURM_CONF" > "$tmp/slurmctld.out" 2>&1 &
pids+=($!)
"${root[@]+"${root[@]}"}" slurmd -D -N "$node" -f "$SLURM_CONF" > "$tmp/slurmd.out" 2>&1 &
pids+=($!)
for ((i = 0; i < 60; ++i)); do
    state=$(sinfo -h -n "$node" -o %T 2> /dev/null || true)
    [[ $state == idle* ]] && break
    sleep 1
done
if [[ $state != idle* ]]; then
    echo "FAIL: the Slurm node did not come up (state \"$state\")"
    tail -n 20 "$tmp/slurmctld.log" "$tmp/slurmd.log" "$tmp"/*.out 2> /dev/null || true
    exit 1
fi

# One row per scene x brick size x culling mode: 4 points in 3 shards, no accuracy, small image.
sweep=(--scenes scenes/spheres.json,scenes/fractal.json --brick-sizes 0.25 --cull on,off --width 64 --height 48
       --warmup 0 --repeat 1 --no-accuracy)
ids=$(tools/slurm-sweep.sh --shards 3 --out "$tmp/out/sweep" --sdfbrick "$bin" -- "${sweep[@]}")
echo "submitted: $ids"
for ((i = 0; i < 600; ++i)); do
    [[ -z $(squeue -h 2> /dev/null) ]] && break
    sleep 1
done
[[ -z $(squeue -h) ]] || { echo "FAIL: jobs still queued after 10 minutes"; squeue; exit 1; }
for log in "$tmp"/out/*.log; do echo "== $log"; cat "$log"; done
[[ -s $tmp/out/sweep.csv ]] || { echo "FAIL: the merge job wrote no CSV"; exit 1; }

"$bin" sweep "${sweep[@]}" --out "$tmp/one" > /dev/null
# Equal rows, timing and rate columns aside (their values are measurements).
/usr/bin/python3 - "$tmp/out/sweep.csv" "$tmp/one.csv" << 'EOF'
import csv, re, sys
timing = re.compile(r"(_ms|_cv|per_second|gbps|bandwidth_fraction|peak_.*)$")
def rows(path):
    with open(path, newline="") as f:
        table = list(csv.DictReader(f))
    return [{k: v for k, v in r.items() if not timing.search(k)} for r in table]
merged, single = rows(sys.argv[1]), rows(sys.argv[2])
if merged != single:
    print(f"FAIL: the merged shards differ from the single-process sweep ({len(merged)} vs {len(single)} rows)")
    for a, b in zip(merged, single):
        print({k: (a[k], b.get(k)) for k in a if a[k] != b.get(k)})
    sys.exit(1)
print(f"merged shards equal the single-process sweep: {len(merged)} rows, {len(merged[0])} columns compared")
EOF

# Shards from machines with different vendors merge into one vendor comparison: the same shards
# relabelled as another machine's device stand in for a second cluster's, then merge and chart.
/usr/bin/python3 - "$tmp/out/sweep.json" "$tmp/other.json" << 'EOF'
import json, sys
sweep = json.load(open(sys.argv[1]))
for p in sweep["points"]:
    p["key"] = p["key"].replace("device=" + p["device"], "device=Other GPU")
    p.update(device="Other GPU", vendor="Other Vendor", driver="0.0", platform="Other platform")
json.dump(sweep, open(sys.argv[2], "w"))
EOF
"$bin" merge "$tmp/out/sweep.json" "$tmp/other.json" --out "$tmp/vendors" > /dev/null
/usr/bin/python3 tools/sweep_charts.py "$tmp/vendors.csv" --out "$tmp/charts" > /dev/null
for scene in spheres fractal; do
    [[ -s $tmp/charts/vendors_$scene.png ]] || { echo "FAIL: no vendor comparison chart for $scene"; exit 1; }
done
echo "shards of two vendors merged into one vendor comparison per scene"
