#!/usr/bin/env bash
# Regenerate the figures and numbers of docs/vehicles.md (run from the repository root, with
# railexu installed): the shipped wagon (empty, loaded) and the extended coach in the seed
# scenario, in two curves and in the critical-speed analysis, and the coach's linear critical
# speed with rigid yaw-damper bushes. About 15 minutes on 2 cores. Writes
# docs/img/vehicles_*.png and prints the tables. A run that stops (exit code 1: derailed,
# diverged) keeps its results and is reported in the tables.
set -euo pipefail
out=${1:-runs/vehicles}
mkdir -p "$out" docs/img
for v in hbbins_empty hbbins_loaded manchester_coach_extended; do
    # the seed scenario: 10 m/s, 2 mm initial offset, 150 m, ideal straight track
    railexu run "$v" --out "$out/${v}_seed" --quiet --plots none || true
    # R 300 m, 150 mm cant (EN 14363 small-radius zone) at 80 km/h: 101 mm cant deficiency
    # (615 m and 595 m: the rearmost wheelset starts 1 m into the track, the coach's leading one
    # 22.6 m ahead of it, and the run must end before the geometry does)
    railexu run "$v" --track curve_r300 --speed '80 km/h' --distance 615 --initial-lateral 0 \
        --out "$out/${v}_r300" --quiet --plots none || true
    # R 600 m, 100 mm cant at 100 km/h: 97 mm cant deficiency
    railexu run "$v" --track curve_r600 --speed '100 km/h' --distance 595 --initial-lateral 0 \
        --out "$out/${v}_r600" --quiet --plots none || true
    # linear critical speed, nonlinear bisection (4 mm disturbance, 3 mm threshold, 300 m per
    # run, 1 m/s bracket) and ramp (0.5 m/s^2 down from the top speed): the wagons up to
    # 60 m/s (above their 120 km/h), the coach up to 120 m/s
    top=60
    if [ "$v" = manchester_coach_extended ]; then top=120; fi
    railexu critical-speed "$v" --methods linear,bisection,ramp --speed-min 10 \
        --speed-max "$top" --tolerance 1 --out "$out/${v}_cs" --quiet || true
done
# the classic check: the coach's yaw dampers without their bushes' series stiffness
railexu critical-speed manchester_coach_extended --methods linear --speed-min 10 \
    --speed-max 120 --set 'suspension.yaw_damper_*.series_stiffness=1e10' \
    --out "$out/manchester_coach_extended_rigid_bushes_cs" --quiet || true
python docs/vehicle_figures.py "$out" docs/img
