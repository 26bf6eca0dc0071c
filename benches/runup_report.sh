#!/usr/bin/env bash
# Regenerates the run-up table of the README: wall time, steps and right-hand-side evaluations of
# the reference run-up (20 s and the full 178.375 s) for each integrator and back end, one run
# at a time, release build, without plots. Usage: bash benches/runup_report.sh > report.md
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build -q --release
out=$(mktemp -d)
echo "| t_end | backend | integrator | steps | rejected | rhs evals | sample evals | wall s |"
echo "|---|---|---|---|---|---|---|---|"
for t in 20 178.375; do
  for b in generated interpreted; do
    for m in dopri5 rk4 sdirk4; do
      ./target/release/washdyn run reference --t-end "$t" --backend "$b" --integrator "$m" \
        --no-plots --out "$out/$b-$m" > /dev/null
      python3 - "$out/$b-$m/summary.json" "$t" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(f"| {sys.argv[2]} | {s['backend']} | {s['integrator']} | {s['steps']} | {s['rejected_steps']} | "
      f"{s['rhs_evals']} | {s['sample_evals']} | {s['wall_time_s']:.2f} |")
PY
    done
  done
done
rm -rf "$out"
