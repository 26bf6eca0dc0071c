#!/usr/bin/env bash
# Regenerates docs/damper-mass.md (issue 21): the reference run-up with the friction dampers'
# moving parts (scene `damper_mass`) against the massless elements (scene `full`), run with each
# implicit method, `auto` and dopri5, then compared with `washdyn compare` on rodas4's runs.
# Usage: bash scripts/damper-mass.sh   (release build; the runs take several minutes in all)
# METHODS (default "rodas4 galpha sdirk4 auto dopri5") selects the methods; ENERGY=1 adds
# `--energy` to every run, so the summaries carry the energy closure (it costs wall time);
# RUNS=0 reuses the runs in out/damper-mass and only compares and writes the document.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build -q --release
bin=./target/release/washdyn
out=out/damper-mass
docs=docs/damper-mass
methods=${METHODS:-rodas4 galpha sdirk4 auto dopri5}
# The channels whose plots the document shows: a tub sensor, the cabinet's side panel, the drum.
keys="tub2_ay cabinet2_ay drum_front_uz"
energy=()
if [ "${ENERGY:-0}" = 1 ]; then energy=(--energy); fi
mkdir -p "$out"
runs=()
for m in $methods; do
  for sc in full damper_mass; do
    budget=()
    # dopri5 stops with its typed error when the step budget is spent (summary.json keeps it).
    if [ "$m" = dopri5 ]; then budget=(--max-steps 3000000); fi
    if [ "${RUNS:-1}" = 1 ]; then
      echo "washdyn run reference --scene $sc --integrator $m ${budget[*]} ${energy[*]}" >&2
      "$bin" run reference --scene "$sc" --integrator "$m" "${budget[@]}" "${energy[@]}" \
        --no-plots --out "$out/$sc-$m" > "$out/$sc-$m.log" 2>&1 \
        || echo "  stopped with an error: $(tail -1 "$out/$sc-$m.log")" >&2
    fi
    runs+=("$out/$sc-$m")
  done
done

rm -rf "$docs"
"$bin" compare "$out/full-rodas4" "$out/damper_mass-rodas4" --out "$docs" \
  --label-a massless --label-b "with mass" > /dev/null

# The key channels' plots go to docs/; the other channels' stay under out/ (regenerable).
mkdir -p "$out/compare"
mv "$docs"/*.png "$out/compare/"
shown=()
for k in $keys; do
  for kind in order tracks; do
    f="$out/compare/${k}_${kind}_compare.png"
    if [ -f "$f" ]; then cp "$f" "docs/damper-mass_${k}_${kind}.png"; fi
  done
  shown+=("$k")
done

python3 - "$docs/compare.md" "${shown[@]}" -- "${runs[@]}" > docs/damper-mass.md <<'PY'
import json, os, sys
args = sys.argv[1:]
compare_md, rest = args[0], args[1:]
sep = rest.index("--")
keys, runs = rest[:sep], rest[sep + 1:]
print("""# The friction dampers' moving parts (issue 21)

Written by `bash scripts/damper-mass.sh`; do not edit by hand.

The reference machine's 178 s run-up (0 to 1400 rpm, rigid bodies) in two scenes of
`models/data/reference.toml`: `full`, where each of the four friction dampers is a massless
element between tub and cabinet, and `damper_mass`, where each damper's moving part is a body of
its own (0.55 kg, 1.69e-3 kg m^2, about 1/100 of the tub's mass) on rubber bearings of 5e5 N/m,
the friction acting between it and the housing (`model/src/equations/part.rs`,
`model/src/elements/damper_joint.rs`). Each scene ran with rodas4, galpha, sdirk4, auto and
dopri5 (`washdyn run reference --scene S --integrator M --no-plots`, default tolerance 1e-6,
generated back end; dopri5 with `--max-steps 3000000`), one run at a time; the comparison
below is of the two rodas4 runs (`washdyn compare`).

## What each run cost
""")
print("| scene | method | completed | t reached s | steps | rejected | wall s | energy closure |")
print("|---|---|---|---|---|---|---|---|")
for r in runs:
    p = os.path.join(r, "summary.json")
    if not os.path.exists(p):
        print(f"| {os.path.basename(r)} | - | no summary | - | - | - | - | - |")
        continue
    s = json.load(open(p))
    done = "yes" if s.get("status") == "ok" else f"{s.get('status')}: {s.get('error', '')}"
    ec = s.get("energy_closure")
    print(f"| {s['scene']} | {s['integrator']} | {done.replace('|', '/')} | "
          f"{s['t_reached']:.3f} | {s['steps']} | {s['rejected_steps']} | "
          f"{s['wall_time_s']:.2f} | {'-' if ec is None else f'{ec:.1e}'} |")
print("""
Wall times: the 2-core machine is shared, so they carry whatever else ran beside the script
(other builds); steps and rejected steps do not depend on it. Energy closure: `-` where the runs
were made without `--energy` (the script's default, so the wall times are the integrators' own;
`ENERGY=1` adds it). A failed run stopped with its typed error at the time given; its summary
keeps the error.
""")
text = open(compare_md).read()
# The comparison's own headings one level down, under this document's.
lines = []
for line in text.splitlines():
    if line.startswith("#"):
        line = "#" + line
    lines.append(line)
print("## The comparison (rodas4)\n")
print("\n".join(lines[1:]).strip())
print("\n## Order plots of key channels\n")
for k in keys:
    for kind, what in (("order", "order plots side by side (one colour scale)"),
                       ("tracks", "order tracks, massless solid, with mass dashed")):
        f = f"damper-mass_{k}_{kind}.png"
        if os.path.exists(os.path.join("docs", f)):
            print(f"{k}: {what}\n\n![{k} {kind}]({f})\n")
        elif kind == "order":
            print(f"{k}: zero throughout in both runs (no plot).\n")
PY
echo "wrote docs/damper-mass.md" >&2
