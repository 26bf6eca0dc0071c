#!/usr/bin/env bash
# Regenerates the run-up table of docs/performance-log.md: wall time, steps and right-hand-side evaluations of
# the reference run-up (20 s and the full 178.375 s) for each integrator and back end, one run
# at a time, release build, without plots. Usage: bash benches/runup_report.sh > report.md
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build -q --release
out=$(mktemp -d)
# SCENES (default "full elastic") and TIMES (default "20 178.375") select the rows; rk4 runs
# at the rigid scenes' step only (the elastic scene needs ~35 us, see docs/performance-log.md).
scenes=${SCENES:-full elastic}
times=${TIMES:-20 178.375}
echo "| scene | t_end | backend | integrator | steps | rejected | rhs evals | sample evals | wall s |"
echo "|---|---|---|---|---|---|---|---|---|"
for sc in $scenes; do
for t in $times; do
  for b in generated interpreted; do
    for m in dopri5 rk4 sdirk4; do
      if [ "$sc" = elastic ] && [ "$m" = rk4 ]; then continue; fi
      ./target/release/washdyn run reference --scene "$sc" --t-end "$t" --backend "$b" \
        --integrator "$m" --no-plots --out "$out/$b-$m" > /dev/null || true
      python3 - "$out/$b-$m/summary.json" "$t" "$sc" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(f"| {sys.argv[3]} | {sys.argv[2]} | {s['backend']} | {s['integrator']} | {s['steps']} | "
      f"{s['rejected_steps']} | {s['rhs_evals']} | {s['sample_evals']} | {s['wall_time_s']:.2f} |")
PY
    done
  done
done
done
rm -rf "$out"
