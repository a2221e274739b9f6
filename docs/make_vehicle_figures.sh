#!/usr/bin/env bash
# Regenerate the figures and numbers of docs/vehicles.md (run from the repository root, with
# railexu installed): the shipped wagon (empty, loaded) and the extended coach in the seed
# scenario, in the R 300 m curve and in the critical-speed analysis. About 15 minutes on 2 cores
# (the bisections dominate). Writes docs/img/vehicles_*.png and prints the tables.
set -euo pipefail
out=${1:-runs/vehicles}
mkdir -p "$out" docs/img
vehicles="hbbins_empty hbbins_loaded manchester_coach_extended"
for v in $vehicles; do
    # the seed scenario: 10 m/s, 2 mm initial offset, 150 m, ideal straight track
    railexu run "$v" --out "$out/${v}_seed" --quiet --plots none
    # the R 300 m curve (150 mm cant, EN 14363 small-radius zone) at 80 km/h: 102 mm cant
    # deficiency; the whole track (640 m), from the centred position
    railexu run "$v" --track curve_r300 --speed '80 km/h' --distance 640 --initial-lateral 0 \
        --out "$out/${v}_r300" --quiet --plots none
    # linear critical speed and the nonlinear bisection (4 mm disturbance, 3 mm threshold,
    # 300 m per run, 1 m/s bracket) between 10 and 60 m/s
    railexu critical-speed "$v" --methods linear,bisection --speed-min 10 --speed-max 60 \
        --tolerance 1 --out "$out/${v}_cs" --quiet
done
python docs/vehicle_figures.py "$out" docs/img
