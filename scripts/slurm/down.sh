#!/usr/bin/env bash
# Stop the one-node Slurm that scripts/slurm/up.sh started in DIR: cancel its jobs and wait for
# an empty queue (job processes outlive the daemons), then stop slurmd, slurmctld and munged by
# their pid files (TERM, then KILL after 10 s). DIR and its files are left; safe to run again
# or on a cluster that is not running. Usage: bash scripts/slurm/down.sh DIR
# DOWN_TIMEOUT (default 60 s) bounds the wait for the queue to empty.
set -euo pipefail

die() {
  echo "down.sh: $*" >&2
  exit 1
}

[ $# -eq 1 ] || die "usage: down.sh DIR"
[ -d "$1" ] || exit 0
dir=$(cd "$1" && pwd)
export SLURM_CONF=$dir/slurm.conf
timeout=${DOWN_TIMEOUT:-60}

# The pid in FILE if that process is alive.
alive() {
  local pid
  [ -s "$1" ] || return 1
  pid=$(cat "$1")
  kill -0 "$pid" 2>/dev/null
}

if alive "$dir/slurmctld.pid" && command -v squeue >/dev/null 2>&1; then
  scancel --user="$(id -un)" 2>/dev/null || true
  deadline=$((SECONDS + timeout))
  while [ -n "$(squeue -h -o %i 2>/dev/null || true)" ]; do
    if [ "$SECONDS" -ge "$deadline" ]; then
      echo "down.sh: jobs still queued after ${timeout} s; stopping the daemons anyway:" >&2
      squeue >&2 || true
      break
    fi
    sleep 0.2
  done
fi

# TERM, then KILL after 10 s; the pid file removed once the process is gone.
stop() {
  local file=$dir/$1.pid pid
  if ! alive "$file"; then
    rm -f "$file"
    return 0
  fi
  pid=$(cat "$file")
  kill -TERM "$pid" 2>/dev/null || true
  for _ in $(seq 50); do
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.2
  done
  if kill -0 "$pid" 2>/dev/null; then
    echo "down.sh: $1 ($pid) ignored TERM for 10 s: KILL" >&2
    kill -KILL "$pid" 2>/dev/null || true
  fi
  rm -f "$file"
}
stop slurmd
stop slurmctld
stop munged
