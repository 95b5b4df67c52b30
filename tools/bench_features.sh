#!/bin/sh
# Render time of the shader specialised to each scene against the all-features shader, for both
# integrators (measured in BENCHMARKS.md's "Textures, sky boxes and per-scene specialisation" section,
# dropped from it in b773538: `git show b773538^:BENCHMARKS.md`).
# Usage: tools/bench_features.sh [vkrt binary]   (default: target/release/vkrt)
# Prints one line per scene x integrator: render seconds specialised, all-features, speed-up.
set -eu
VKRT=${1:-target/release/vkrt}
LAB=../shared/scenes/lab
OUT=${TMPDIR:-/tmp}/vkrt-bench-features
mkdir -p "$OUT"
seconds() { sed -n 's/.* in \([0-9.]*\) s on .*/\1/p'; }
run() { # name integrator extra-args...
    name=$1; integ=$2; shift 2
    s=$("$VKRT" render "$@" --integrator "$integ" -o "$OUT/$name-$integ.png" 2>&1 | seconds)
    a=$("$VKRT" render "$@" --integrator "$integ" --all-features -o "$OUT/$name-$integ-all.png" 2>&1 | seconds)
    echo "$name $integ specialised ${s}s all-features ${a}s speed-up $(echo "scale=2; $a / $s" | bc)"
}
W="--width 512 --height 384"
P="--width 256 --height 192 --spp 16 --max-depth 8"
for integ in whitted path; do
    if [ $integ = whitted ]; then A=$W; else A=$P; fi
    run cornell_box $integ $LAB/cornell_box/cornell_box.yaml $A
    run Box_ver_path $integ $LAB/Box_ver_path/Box_ver_path.yaml $A
    run floor $integ $LAB/floor/floor.yaml $A
    run teapot $integ $LAB/teapot/teapot.yaml $A
    run bunny $integ $LAB/bunny/bunny.yaml $A
    run white_oak $integ $LAB/white_oak/white_oak.yaml $A
    run sponza_sky $integ scenes/bench/sponza.yaml --sky 1,1,1 $A
done
# The seed report's case: White Oak, Whitted depth 7, 1024x768, with its textures.
"$VKRT" render $LAB/white_oak/white_oak.yaml --width 1024 --height 768 --max-depth 7 -o "$OUT/white_oak_1024.png" 2>&1 | tail -1
