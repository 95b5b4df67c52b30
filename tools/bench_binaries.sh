#!/usr/bin/env bash
# Compares vkrt binaries (e.g. before/after a change, built from different commits) on the same
# rays and renders, interleaved round by round so a slow spell of this shared machine hits every
# binary alike. Prints one Markdown row per binary and workload: the best and the median over
# the rounds.
#
#   [LAYOUTS="threaded wide ..."] tools/bench_binaries.sh ROUNDS NAME=PATH [NAME=PATH ...]
#
# Workloads: `vkrt trace` on Conference and Sponza (SAH), 1M primary rays (the scene's camera,
# 1024^2) and 1M incoherent rays, made by `vkrt rays` (of GEN, default target/release/vkrt);
# a 16 spp 512x512 path-traced render of scenes/cornell-measured and a 1024x768 depth-7 Whitted
# render of White Oak (render seconds as vkrt reports them). Each workload runs once per layout
# in LAYOUTS (default: threaded), so one binary can also compare layouts.
set -euo pipefail
rounds=${1:?usage: tools/bench_binaries.sh ROUNDS NAME=PATH [NAME=PATH ...]}
shift
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
shared=${VKRT_SHARED:-$root/../shared}
gen=${GEN:-$root/target/release/vkrt}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for scene in conference sponza; do
  obj="$shared/scenes/conference/conference.obj"
  [ "$scene" = sponza ] && obj="$shared/scenes/sponza-dabrovic/sponza.obj"
  "$gen" rays "$obj" --kind primary --width 1024 --height 1024 -o "$tmp/$scene-primary.npy" 2>/dev/null
  "$gen" rays "$obj" --kind incoherent --count $((1 << 20)) -o "$tmp/$scene-incoherent.npy" 2>/dev/null
done
declare -A results
for _ in $(seq "$rounds"); do
  for pair in "$@"; do
    for layout in ${LAYOUTS:-threaded}; do
      name="${pair%%=*}/$layout"; bin=${pair#*=}
      for scene in conference sponza; do
        obj="$shared/scenes/conference/conference.obj"
        [ "$scene" = sponza ] && obj="$shared/scenes/sponza-dabrovic/sponza.obj"
        for kind in primary incoherent; do
          rate=$("$bin" trace "$obj" --rays "$tmp/$scene-$kind.npy" --out "$tmp/hits.npy" --layout "$layout" 2>&1 \
            | grep -o '[0-9.]* M rays/s' | head -1 | cut -d' ' -f1)
          results["$name|$scene $kind (M rays/s)"]+="$rate "
        done
      done
      secs=$("$bin" render "$root/scenes/cornell-measured/cornell.yaml" --integrator path --spp 16 --width 512 --height 512 \
        --layout "$layout" -o "$tmp/path.pfm" 2>&1 | grep -o 'in [0-9.]* s on' | cut -d' ' -f2)
      results["$name|path cornell 512^2 16 spp (s)"]+="$secs "
      secs=$("$bin" render "$shared/scenes/lab/white_oak/white_oak.yaml" --width 1024 --height 768 --layout "$layout" \
        -o "$tmp/oak.pfm" 2>&1 | grep -o 'in [0-9.]* s on' | cut -d' ' -f2)
      results["$name|whitted white oak 1024x768 (s)"]+="$secs "
    done
  done
done
echo "| binary | workload | best | median | all rounds |"
echo "|---|---|---:|---:|---|"
for key in $(printf '%s\n' "${!results[@]}" | tr ' ' '~' | sort); do
  k=${key//\~/ }
  vals=${results[$k]}
  # Best: the highest rate or the lowest time; median of the rounds.
  read -r best median < <(tr ' ' '\n' <<<"$vals" | grep . | sort -g | awk -v rate="$([[ $k == *rays/s* ]] && echo 1 || echo 0)" \
    '{v[NR]=$1} END {m = (NR % 2) ? v[(NR+1)/2] : (v[NR/2]+v[NR/2+1])/2; print (rate ? v[NR] : v[1]), m}')
  echo "| ${k%%|*} | ${k#*|} | $best | $median | $vals|"
done
