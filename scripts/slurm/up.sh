#!/usr/bin/env bash
# Start a one-node Slurm (munged, slurmctld, slurmd) whose configuration, state, logs and pid
# files all live in DIR, for `washdyn study run --slurm` and tests/slurm.rs (design notes: "A
# real single-node Slurm on these machines"). Nothing under /etc is read or written.
# Usage: bash scripts/slurm/up.sh DIR   then   export SLURM_CONF=DIR/slurm.conf (printed last).
# Again on a running cluster it only waits for the node and prints the export line.
# Needs the Debian packages slurmctld slurmd slurm-client munge, run as root (SlurmUser=root).
# SLURMCTLD_PORT and SLURMD_PORT (default 6817, 6818) move the daemons' ports; UP_TIMEOUT
# (default 60 s) bounds the wait for the node to be idle.
set -euo pipefail
# The daemons and mungekey live in /usr/sbin, not on every PATH.
export PATH=$PATH:/usr/sbin:/sbin

die() {
  echo "up.sh: $*" >&2
  exit 1
}

[ $# -eq 1 ] || die "usage: up.sh DIR"
for tool in munged mungekey slurmctld slurmd sinfo; do
  command -v "$tool" >/dev/null 2>&1 ||
    die "$tool not found: apt-get install slurmctld slurmd slurm-client munge"
done
mkdir -p "$1"
dir=$(cd "$1" && pwd)
conf=$dir/slurm.conf
ctld_port=${SLURMCTLD_PORT:-6817}
slurmd_port=${SLURMD_PORT:-6818}
timeout=${UP_TIMEOUT:-60}
export SLURM_CONF=$conf

# The pid in FILE if that process is alive.
alive() {
  local pid
  [ -s "$1" ] || return 1
  pid=$(cat "$1")
  kill -0 "$pid" 2>/dev/null
}

# The last lines of every log in DIR, for an error.
tails() {
  local f
  for f in "$dir"/*.log; do
    [ -f "$f" ] || continue
    echo "--- last lines of $f" >&2
    tail -n 15 "$f" >&2
  done
}

# Whether something listens on 127.0.0.1:PORT (bash's /dev/tcp: no extra tool).
listening() {
  (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null
}

mkdir -p "$dir/state" "$dir/spool"
# munged refuses a socket folder others can write to or list: 711 (design notes).
chmod 711 "$dir"

# MUNGE: its own key, socket and files in DIR.
if ! alive "$dir/munged.pid"; then
  [ -s "$dir/munge.key" ] || mungekey --create --keyfile="$dir/munge.key"
  chmod 600 "$dir/munge.key"
  munged --key-file="$dir/munge.key" --socket="$dir/munge.socket" \
    --pid-file="$dir/munged.pid" --log-file="$dir/munged.log" --seed-file="$dir/munged.seed" ||
    {
      tails
      die "munged did not start"
    }
fi

# slurm.conf: this machine's cores and memory as slurmd sees them (a little memory below what
# it reports, which it refuses to exceed); the node and partition names fixed.
if [ ! -s "$conf" ]; then
  cpus=$(nproc)
  mem=$(slurmd -C | sed -n 's/.*RealMemory=\([0-9]*\).*/\1/p')
  [ -n "$mem" ] || die "slurmd -C gave no RealMemory: $(slurmd -C 2>&1)"
  mem=$((mem * 95 / 100))
  cat >"$conf.tmp" <<EOF
# Written by scripts/slurm/up.sh: a one-node cluster in $dir.
ClusterName=washdyn
SlurmctldHost=localhost
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge.socket
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
MailProg=/bin/true
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
ReturnToService=2
MinJobAge=600
MaxArraySize=10001
NodeName=ci1 NodeHostname=localhost NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=ci Nodes=ci1 Default=YES MaxTime=INFINITE State=UP
EOF
  mv "$conf.tmp" "$conf"
fi
# The ports of the configuration in force (an older one may name others).
ctld_port=$(sed -n 's/^SlurmctldPort=//p' "$conf")
slurmd_port=$(sed -n 's/^SlurmdPort=//p' "$conf")

# The daemons, each in its own session (they outlive this script) with its pid saved.
start() {
  local name=$1 port=$2
  shift 2
  alive "$dir/$name.pid" && return 0
  listening "$port" &&
    die "port $port is taken (another Slurm?): stop it, or set SLURMCTLD_PORT/SLURMD_PORT and remove $conf"
  setsid "$@" >>"$dir/$name.out" 2>&1 </dev/null &
  echo $! >"$dir/$name.pid"
}
start slurmctld "$ctld_port" slurmctld -D -f "$conf"
start slurmd "$slurmd_port" slurmd -N ci1 -D -f "$conf"

# Ready when the node is idle (mixed or allocated on a cluster already running jobs).
deadline=$((SECONDS + timeout))
state=
while :; do
  state=$(sinfo -h -N -o %T 2>/dev/null || true)
  case $state in
  idle | mixed | allocated) break ;;
  esac
  for d in slurmctld slurmd; do
    if ! alive "$dir/$d.pid"; then
      tails
      tail -n 15 "$dir/$d.out" >&2 || true
      die "$d exited"
    fi
  done
  if [ "$SECONDS" -ge "$deadline" ]; then
    tails
    die "node ci1 not idle after ${timeout} s (sinfo: '${state:-no answer}')"
  fi
  sleep 0.2
done
echo "export SLURM_CONF=$conf"
