#!/usr/bin/env bash
# make test-slurm: the smoke workflow through profiles/slurm on a single-node SLURM of this machine.
#
# Installs SLURM (slurmctld, slurmd, slurmdbd), munge and MariaDB from the system's packages if missing, starts
# them with a private configuration under a scratch directory (accounting in slurmdbd, so that sacct, which the
# executor plugin queries for job states, knows every job), runs the smoke workflow twice (locally, and through
# profiles/slurm), checks that the SLURM run submitted its jobs with sbatch and that sacct shows each of them
# COMPLETED, compares the result files of the two runs, and stops the daemons. Needs root; not in the default tests.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BIN=$ROOT/.venv/bin
S=$(mktemp -d /tmp/capslide-slurm.XXXXXX)
HOST=$(hostname -s)
say() { printf '\n== %s\n' "$*"; }

[ "$(id -u)" -eq 0 ] || { echo "test-slurm: needs root (it installs and starts daemons)" >&2; exit 2; }
if [ -e /etc/slurm/slurm.conf ] || [ -e /etc/slurm/slurmdbd.conf ]; then
    echo "test-slurm: /etc/slurm/slurm.conf exists: this machine has a SLURM configuration; not touching it" >&2; exit 2
fi
for port in 6817 6818 6819; do
    if (: < /dev/tcp/127.0.0.1/$port) 2>/dev/null; then
        echo "test-slurm: port $port is in use: is a SLURM already running here?" >&2; exit 2
    fi
done

say "packages"
if ! command -v slurmctld >/dev/null || ! command -v slurmdbd >/dev/null || ! command -v mariadbd >/dev/null \
    || ! command -v munged >/dev/null; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q slurm-wlm slurmdbd munge mariadb-server >"$S/apt.log"
fi
slurmctld -V

mkdir -p "$S"/{state,spool,log,run,db,local,cluster}
# The configuration where the packages look for it (the job steps' srun reads /etc/slurm, not SLURM_CONF);
# removed again at the end.
ETC=/etc/slurm
MUNGE_PID=
cleanup() {
    status=$?
    say "stopping the daemons"
    scontrol shutdown >/dev/null 2>&1 || true
    sleep 2
    for pid in "$S"/run/*.pid; do [ -f "$pid" ] && kill "$(cat "$pid")" 2>/dev/null || true; done
    [ -n "$MUNGE_PID" ] && kill "$MUNGE_PID" 2>/dev/null || true
    rm -f "$ETC/slurm.conf" "$ETC/slurmdbd.conf"
    sleep 1
    pgrep -a -f "$S" >/dev/null && { echo "still running:"; pgrep -a -f "$S"; } || echo "all stopped"
    if [ "$status" -eq 0 ]; then rm -rf "$S"; else echo "test-slurm: FAILED; logs in $S/log" >&2; fi
    exit "$status"
}
trap cleanup EXIT

say "munge"
if ! munge -n </dev/null >/dev/null 2>&1; then
    install -d -o munge -g munge -m 0755 /run/munge
    runuser -u munge -- munged --pid-file=/run/munge/munged.pid
    MUNGE_PID=$(cat /run/munge/munged.pid)
fi
munge -n | unmunge | grep STATUS

say "MariaDB (private data directory, 127.0.0.1:3307)"
mariadb-install-db --no-defaults --datadir="$S/db" --user=root --auth-root-authentication-method=normal \
    >"$S/log/mariadb-install.log" 2>&1
mariadbd --no-defaults --datadir="$S/db" --user=root --socket="$S/run/mysql.sock" --port=3307 \
    --bind-address=127.0.0.1 --pid-file="$S/run/mariadb.pid" --log-error="$S/log/mariadb.log" 2>>"$S/log/mariadb.log" &
for _ in $(seq 60); do mariadb-admin --no-defaults -S "$S/run/mysql.sock" -u root ping >/dev/null 2>&1 && break; sleep 1; done
mariadb --no-defaults -S "$S/run/mysql.sock" -u root -e "
    CREATE USER 'slurm'@'127.0.0.1' IDENTIFIED BY 'capslide'; CREATE USER 'slurm'@'localhost' IDENTIFIED BY 'capslide';
    GRANT ALL ON slurm_acct_db.* TO 'slurm'@'127.0.0.1'; GRANT ALL ON slurm_acct_db.* TO 'slurm'@'localhost';"

say "slurmdbd, slurmctld, slurmd ($HOST, $(nproc --all) CPUs)"
cat >"$ETC/slurmdbd.conf" <<EOF
AuthType=auth/munge
DbdHost=localhost
SlurmUser=root
PidFile=$S/run/slurmdbd.pid
LogFile=$S/log/slurmdbd.log
StorageType=accounting_storage/mysql
StorageHost=127.0.0.1
StoragePort=3307
StorageUser=slurm
StoragePass=capslide
StorageLoc=slurm_acct_db
EOF
chmod 600 "$ETC/slurmdbd.conf"
MEM=$(( $(free -m | awk '/^Mem:/ {print $2}') * 9 / 10 ))
cat >"$ETC/slurm.conf" <<EOF
ClusterName=capslide
SlurmctldHost=$HOST
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$S/state
SlurmdSpoolDir=$S/spool
SlurmctldPidFile=$S/run/slurmctld.pid
SlurmdPidFile=$S/run/slurmd.pid
SlurmctldLogFile=$S/log/slurmctld.log
SlurmdLogFile=$S/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/linux
AccountingStorageType=accounting_storage/slurmdbd
AccountingStorageHost=localhost
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
MinJobAge=600
NodeName=$HOST CPUs=$(nproc --all) RealMemory=$MEM State=UNKNOWN
PartitionName=capslide Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
EOF
slurmdbd
for _ in $(seq 60); do sacctmgr -n show cluster >/dev/null 2>&1 && break; sleep 1; done
sacctmgr -i add cluster capslide >/dev/null
sacctmgr -i add account capslide Description=test-slurm Organization=capslide >/dev/null
sacctmgr -i add user root Account=capslide DefaultAccount=capslide >/dev/null
slurmctld
slurmd
for _ in $(seq 60); do sinfo -h -o %t 2>/dev/null | grep -q idle && break; sleep 1; done
sinfo

copy_workflow() {  # a scratch copy of the workflow, as the workflow tests use it
    for name in Snakefile workflow config src profiles; do cp -r "$ROOT/$name" "$1/"; done
}
copy_workflow "$S/local"
copy_workflow "$S/cluster"

say "the smoke workflow, locally"
(cd "$S/local" && "$BIN/snakemake" --cores 2 --configfile config/smoke.yaml -q >"$S/log/local.log" 2>&1)
echo "done: $(find "$S/local/results" -name '*.nc' | wc -l) netCDF files"

say "the smoke workflow through profiles/slurm"
START=$(date +%Y-%m-%dT%H:%M:%S)
(cd "$S/cluster" && "$BIN/snakemake" --profile profiles/slurm --configfile config/smoke.yaml \
    --default-resources mem_mb=2000 runtime=30 slurm_account=capslide slurm_partition=capslide \
    --latency-wait 5 2>&1 | tee "$S/log/cluster.log" | grep -E "submitted|Finished|Error|error" || true)
grep -q "steps (100%) done" "$S/log/cluster.log" || { tail -30 "$S/log/cluster.log"; exit 1; }

say "sacct: every submitted job"
mapfile -t SUBMITTED < <(grep -oE "SLURM jobid [0-9]+|SLURM job ID [0-9]+" "$S/log/cluster.log" \
    | grep -oE "[0-9]+$" | sort -u)
sacct -X -P -S "$START" --format=JobID,JobName%40,Partition,Account,AllocCPUS,State,ExitCode,Elapsed | tee "$S/log/sacct.txt"
[ "${#SUBMITTED[@]}" -gt 0 ] || { echo "no job went through sbatch" >&2; exit 1; }
for id in "${SUBMITTED[@]}"; do
    grep -qE "^$id\|.*\|COMPLETED\|0:0\|" "$S/log/sacct.txt" || { echo "job $id is not COMPLETED in sacct" >&2; exit 1; }
done
echo "${#SUBMITTED[@]} jobs submitted with sbatch, each COMPLETED with exit code 0 in sacct"

say "results: SLURM run against local run"
"$BIN/python" "$ROOT/benchmarks/compare_results.py" "$S/local/results" "$S/cluster/results" --rtol 0
cmp "$S"/local/results/*/config.yaml "$S"/cluster/results/*/config.yaml && echo "results/NAME/config.yaml identical"
say "test-slurm passed"
