#!/bin/sh
# Regenerates every figure and every printed output that README.md shows, from the models
# and scenarios in this folder, with the project's own commands. Run from anywhere:
#
#     models/teaching/regenerate.sh
#
# BONDGRAPH names the program (default: the release build of this checkout, built first).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
if [ -z "${BONDGRAPH:-}" ]; then
    (cd "$root" && cargo build --release --quiet)
    BONDGRAPH="$root/target/release/bondgraph"
fi
cd "$here"
mkdir -p figures

for model in rc mass_spring_damper quarter_car dc_motor tank thermal; do
    "$BONDGRAPH" check "$model.ron" > "figures/$model.check.txt"
    "$BONDGRAPH" equations "$model.ron" > "figures/$model.equations.txt"
    "$BONDGRAPH" equations "$model.ron" --format latex > "figures/$model.equations.tex"
    # Commands that landed after this folder was written: used where the program has them.
    if "$BONDGRAPH" analyze --help > /dev/null 2>&1; then
        "$BONDGRAPH" analyze "$model.ron" > "figures/$model.analyze.txt" 2>&1 || true
    fi
    if "$BONDGRAPH" explain --help > /dev/null 2>&1; then
        "$BONDGRAPH" explain "$model.ron" > "figures/$model.explain.txt" 2>&1 || true
    fi
done

simulate() { # model scenario [--panel ...]
    model=$1
    scenario=$2
    shift 2
    "$BONDGRAPH" simulate "$model.ron" --scenario "scenarios/$scenario.ron" \
        --out "figures/$scenario.csv" --plot "figures/$scenario.svg" "$@" 2> /dev/null
}

simulate rc rc_step \
    --panel effort:capacitor,effort:resistor --panel flow:capacitor \
    --panel energy:supplied,energy:stored,energy:dissipated
simulate mass_spring_damper msd_release \
    --panel flow:mass --panel effort:spring \
    --panel energy:mass,energy:spring,energy:stored,energy:dissipated
simulate quarter_car quarter_car_bump \
    --panel integral:flow:wheel,integral:flow:body --panel flow:body --panel effort:tyre \
    --panel energy:supplied,energy:stored,energy:dissipated
simulate dc_motor dc_motor_step \
    --panel flow:winding_inductance --panel flow:load_inertia \
    --panel power:supply,power:winding_resistance,power:load_friction
simulate tank tank_fill --panel effort:tank --panel flow:valve --panel integral:flow:tank
simulate thermal thermal_cooling --panel effort:body --panel flow:wall,flow:heater
echo "regenerated $(ls figures | wc -l) files in models/teaching/figures/"
