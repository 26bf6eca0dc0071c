#!/usr/bin/env bash
# The whole run-up with every mode of the modal data (issue 21's modes to 2 kHz): the reference
# model file with a scene `every_mode`, `elastic` without `max_order` (405 coordinates; not a
# built-in scene: docs/elastic-machine.md), run interpreted.
# Usage: bash scripts/every-mode.sh OUT [washdyn run options]
# Writes OUT/every.toml and the run into OUT/run. Without options it runs the measured
# setting, `--integrator galpha --tol 1e-5` (801 937 steps, 6443 s on one core); any option
# given replaces it (e.g. `--integrator auto --tol 1e-6 --t-end 20`). The script sets
# `--scene`, `--no-plots`, `--max-projected-wall inf` and `--out`.
set -euo pipefail
out=${1:?usage: bash scripts/every-mode.sh OUT [washdyn run options]}
shift
root=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
# The data files are named relative to models/data; the copy names them absolutely.
sed "s|\"\.\./fe/|\"$root/models/fe/|" "$root/models/data/reference.toml" >"$out/every.toml"
cat >>"$out/every.toml" <<'SCENE'

# Every mode of the data: `elastic` without `max_order` (scripts/every-mode.sh).
[[scenes]]
name = "every_mode"
effects = ["gyroscopic", "unbalance.drum", "unbalance.motor", "friction_dampers", "gasket_damping",
           "element_geometry", "unbalance_inertia", "elastic.tub", "elastic.drum",
           "elastic.cabinet", "centrifugal_stiffening"]
SCENE
opts=("$@")
if [ ${#opts[@]} -eq 0 ]; then opts=(--integrator galpha --tol 1e-5); fi
cargo build -q --release --manifest-path "$root/Cargo.toml"
"$root/target/release/washdyn" run "$out/every.toml" --scene every_mode --no-plots \
    --max-projected-wall inf --out "$out/run" "${opts[@]}"
