#!/usr/bin/env bash
# Time to error of the environment map's importance sampling (issue 19): the reference scene of
# tests/path_envmap.rs (scenes/envmap, tests/refs/envmap-sun.exr, 256x256) rendered with the
# defaults (light sampling of the map, MIS) and with --no-nee (BSDF sampling alone), against the
# Mitsuba reference, at each spp given (default 16 64 256). Prints one table row per run, with
# mean HDR-FLIP beside relMSE when flip-evaluator and mitsuba are installed (pip install
# flip-evaluator mitsuba; tools/path_time_to_error.py's flip_hdr), "-" otherwise.
# Usage: tools/bench-envmap.sh [SPP...]
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q
bin=target/release/vkrt
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(nproc) cores"
echo "| sampling | spp | seconds | relMSE | relMSE x s | HDR-FLIP |"
echo "|---|---:|---:|---:|---:|---:|"
flip() {
  python3 -c "import sys; sys.path.insert(0, 'tools'); from path_time_to_error import flip_hdr; f = flip_hdr(sys.argv[1], sys.argv[2]); print('-' if f is None else f'{f:.4f}')" "$1" "$2"
}
spps=("$@"); [ ${#spps[@]} -eq 0 ] && spps=(16 64 256)
for spp in "${spps[@]}"; do
  for mode in importance bsdf-only; do
    flags=(); [ "$mode" = bsdf-only ] && flags=(--no-nee)
    start=$(date +%s.%N)
    "$bin" render scenes/envmap/envmap-scene.obj --envmap tests/refs/envmap-sun.exr --eye 3,2.2,4.5 --target 0,0.4,0 \
      --fov 40 --width 256 --height 256 --integrator path --spp "$spp" "${flags[@]}" -o "$out/$mode.exr" --quiet
    end=$(date +%s.%N)
    relmse=$("$bin" compare "$out/$mode.exr" tests/refs/envmap-256.exr | awk '/^relmse/ {print $2}')
    f=$(flip "$out/$mode.exr" tests/refs/envmap-256.exr)
    awk -v m="$mode" -v n="$spp" -v a="$start" -v b="$end" -v r="$relmse" -v f="$f" \
      'BEGIN { s = b - a; printf "| %s | %d | %.2f | %.3e | %.3e | %s |\n", m, n, s, r, r * s, f }'
  done
done
