#!/usr/bin/env bash
# Whitted render times at 1024x768, depth 7, 1 spp, for the scenes of the foundation issue.
# A benchmark, not a test: prints a Markdown table. Needs ../shared beside the repository.
# Usage: tools/bench-whitted.sh [extra vkrt render flags]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
cargo build --release --quiet --bin vkrt
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
scenes=(
  scenes/lab/cornell_box/cornell_box.yaml
  ../shared/scenes/lab/white_oak/white_oak.yaml
  scenes/bench/conference.yaml
  scenes/bench/sponza.yaml
)
echo "| scene | triangles | BVH build s | render s (1024x768, depth 7) | device |"
echo "|---|---:|---:|---:|---|"
for s in "${scenes[@]}"; do
  log=$(target/release/vkrt render "$s" -o "$out/x.png" --width 1024 --height 768 --max-depth 7 --verbose "$@" 2>&1 | grep -v '^warning')
  tris=$(sed -n 's/^scene [^:]*: \([0-9]*\) triangles.*/\1/p' <<<"$log")
  build=$(sed -n 's/.*BVH build \([0-9.]*\) s.*/\1/p' <<<"$log")
  render=$(sed -n 's/^rendered .* in \([0-9.]*\) s on .*/\1/p' <<<"$log")
  device=$(sed -n 's/^device: //p' <<<"$log")
  echo "| $s | $tris | $build | $render | $device |"
done
