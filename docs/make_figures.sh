#!/usr/bin/env bash
# Regenerate the figures and numbers quoted in docs/ (run from the repository root, with railexu
# installed). Takes a few minutes on 2 cores.
set -euo pipefail
out=${1:-runs/docs}
mkdir -p "$out" docs/img
# the seed scenario: 10 m/s, 2 mm, 150 m
railexu run vehicles/eu07.yaml --out "$out/eu07_10" --quiet
railexu run vehicles/eu07_bogie.yaml --out "$out/bogie_10" --quiet
# the same comparison above the bogie's critical speed
railexu run vehicles/eu07.yaml --speed 45 --distance 600 --out "$out/eu07_45" --quiet
railexu run vehicles/eu07_bogie.yaml --speed 45 --distance 600 --out "$out/bogie_45" --quiet
# the EU07 in the R 300 m curve at 150 mm cant deficiency (docs/curving.md)
railexu run vehicles/eu07.yaml --track tracks/curve_r300.yaml --speed 24.26 --distance 450 \
    --initial-lateral 0 --out "$out/eu07_r300" --quiet
cp "$out/eu07_r300/track.png" docs/img/curve_r300_track.png
cp "$out/eu07_r300/curving.png" docs/img/curve_r300_curving.png
# linear critical speeds
railexu critical-speed vehicles/eu07.yaml --methods linear --out "$out/cs_eu07" --quiet
railexu critical-speed vehicles/eu07_bogie.yaml --methods linear,bisection,ramp \
    --speed-min 10 --speed-max 70 --tolerance 1 --out "$out/cs_bogie" --quiet
# the Manchester contact benchmark
railexu contact --wheel S1002 --rail UIC60 --inclination 1:40 --gauge 1.435 \
    --flange-back 1.360 --radius 0.46 --lateral 0:0.010:0.0005 --yaw-per-lateral 2.4 \
    --load 10000 --speed 2 --friction 0.3 --shear-modulus 82e9 --poisson 0.28 \
    --creep polach --out "$out/manchester"
for f in eu07_10/lateral_displacement eu07_10/lateral_force bogie_10/lateral_displacement \
         bogie_45/lateral_displacement bogie_45/lateral_force eu07_45/lateral_displacement \
         cs_eu07/linear_stability cs_bogie/linear_stability cs_bogie/nonlinear_stability \
         manchester/contact_points manchester/delta_r manchester/conicity; do
    cp "$out/$f.png" "docs/img/$(echo "$f" | tr '/' '_').png"
done
# switches and crossings: slices along a crossing, the wing rail -> nose transfer (docs/switches-and-crossings.md)
python docs/sc_figures.py docs/img
