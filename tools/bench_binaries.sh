#!/usr/bin/env bash
# Compares vkrt binaries (e.g. before/after a change, built from different commits) on the same
# rays and renders, interleaved round by round so a slow spell of this shared machine hits every
# binary alike. Prints one Markdown row per binary and workload: the best and the median over
# the rounds.
#
#   [LAYOUTS="threaded wide ..."] tools/bench_binaries.sh ROUNDS NAME=PATH [NAME=PATH ...]
#
# Workloads: `vkrt trace` on Conference and Sponza (SAH), primary rays (1024^2 pinhole) and 1M
# incoherent rays, both from tools/embree_compare.py's generators (needs numpy); and a 16 spp
# 512x512 path-traced render of scenes/cornell-measured (render seconds as vkrt reports them).
# Each workload runs once per layout in LAYOUTS (default: threaded), so one binary can also
# compare layouts.
set -euo pipefail
rounds=${1:?usage: tools/bench_binaries.sh ROUNDS NAME=PATH [NAME=PATH ...]}
shift
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
shared=${VKRT_SHARED:-$root/../shared}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 - "$tmp" "$shared" "$here" <<'PY'
import sys
sys.path.insert(0, sys.argv[3])
import numpy as np
import embree_compare as e
tmp, shared = sys.argv[1], sys.argv[2]
for name, path in [("conference", f"{shared}/scenes/conference/conference.obj"), ("sponza", f"{shared}/scenes/sponza-dabrovic/sponza.obj")]:
    tris = e.load_obj(path)
    lo, hi = tris.reshape(-1, 3).min(0), tris.reshape(-1, 3).max(0)
    np.save(f"{tmp}/{name}-primary.npy", e.primary_rays(lo, hi, 1024))
    np.save(f"{tmp}/{name}-incoherent.npy", e.incoherent_rays(lo, hi, 1 << 20, np.random.default_rng(1)))
PY
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
            | grep -o '[0-9.]* M rays/s' | cut -d' ' -f1)
          results["$name|$scene $kind (M rays/s)"]+="$rate "
        done
      done
      secs=$("$bin" render "$root/scenes/cornell-measured/cornell.yaml" --integrator path --spp 16 --width 512 --height 512 \
        --layout "$layout" -o "$tmp/path.pfm" 2>&1 | grep -o 'in [0-9.]* s on' | cut -d' ' -f2)
      results["$name|path cornell 512^2 16 spp (s)"]+="$secs "
    done
  done
done
echo "| binary | workload | best | median | all rounds |"
echo "|---|---|---:|---:|---|"
for key in $(printf '%s\n' "${!results[@]}" | tr ' ' '~' | sort); do
  k=${key//\~/ }
  vals=${results[$k]}
  read -r best median < <(python3 -c "
import statistics, sys
v = [float(x) for x in sys.argv[2:]]
print(max(v) if sys.argv[1] == 'rate' else min(v), statistics.median(v))" "$([[ $k == *rays/s* ]] && echo rate || echo secs)" $vals)
  echo "| ${k%%|*} | ${k#*|} | $best | $median | $vals|"
done
