#!/usr/bin/env bash
# Regenerate docs/even-orders.md's run-up tables: the reference with its counterweights tight
# and loose, with and without the kinematic sources of even orders. Whole run-ups, galpha at
# 1e-6, interpreted (model files); about 7 min on one core (quiet), most of it the loose bolts;
# then the elastic cabinet (built-in scenes, generated, about 15 min): the side panels' curves,
# and the counterweights tight and loose (the loose bolts a study of the free torques).
# Usage (from the repository's root, washdyn installed or built): bash docs/even-orders/regenerate.sh [OUT]
set -euo pipefail
out=${1:-out/eo}
washdyn=${WASHDYN:-washdyn}
mkdir -p "$out/models/data"
ln -sfn "$(pwd)/models/fe" "$out/models/fe"
scenes='
[[scenes]]
name = "full_galpha"
effects = ["gyroscopic", "unbalance.drum", "unbalance.motor", "friction_dampers", "gasket_damping",
           "element_geometry", "unbalance_inertia"]
solver = { method = "galpha", tol = 1e-6 }

[[scenes]]
name = "iso_base"
effects = ["gyroscopic", "unbalance.drum", "unbalance.motor", "friction_dampers", "gasket_damping"]
solver = { method = "galpha", tol = 1e-6 }

[[scenes]]
name = "iso_cw"
effects = ["gyroscopic", "unbalance.drum", "unbalance.motor", "friction_dampers", "gasket_damping",
           "counterweights"]
solver = { method = "galpha", tol = 1e-6 }
'
{ cat models/data/reference.toml; echo "$scenes"; } > "$out/models/data/tight.toml"
# Loose: every bolt's tightening torque to zero (no preload).
{ sed 's/torque = { moment = 15.0/torque = { moment = 0.0/' models/data/reference.toml; echo "$scenes"; } \
  > "$out/models/data/loose.toml"
run() { "$washdyn" run "$out/models/data/$1.toml" --scene "$2" --out "$out/$1_$2" --no-plots; }
run tight full_galpha
run tight counterweights
run loose counterweights
run tight iso_base
run tight iso_cw
run loose iso_cw
python3 docs/even-orders/levels.py "$out/tight_full_galpha" "$out/tight_counterweights" \
  "$out/loose_counterweights" "$out/tight_iso_base" "$out/tight_iso_cw" "$out/loose_iso_cw"
# The side panels' curves (built-in scenes, generated): cabinet tables and Figure 14.
"$washdyn" run reference --scene elastic_rigid_tub --out "$out/elastic_rigid_tub" --no-plots
"$washdyn" run reference --scene panel_curves --out "$out/panel_curves" --no-plots
python3 docs/even-orders/levels.py "$out/elastic_rigid_tub" "$out/panel_curves"
python3 docs/even-orders/speed_plot.py cabinet2_ay "$out/even_orders_cabinet2_speed.png" \
  "$out/elastic_rigid_tub" "$out/panel_curves"
# The counterweights' cabinet channels: tight (built-in) and loose (a study setting every
# bolt's free torque to 0, on the same generated code).
"$washdyn" run reference --scene cabinet_counterweights --out "$out/cabinet_counterweights" --no-plots
"$washdyn" study run docs/even-orders/loose_bolts.toml --out "$out/cabinet_loose"
loose="$out/cabinet_loose/variants/variant=0000"
python3 docs/even-orders/levels.py "$out/elastic_rigid_tub" "$out/cabinet_counterweights" "$loose"
python3 docs/even-orders/speed_plot.py cabinet2_ay "$out/cabinet2_speed_counterweights.png" \
  "$out/elastic_rigid_tub" "$out/cabinet_counterweights" "$loose"
