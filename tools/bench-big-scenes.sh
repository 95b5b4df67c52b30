#!/usr/bin/env bash
# tools/bench-big-scenes.sh: the big-scene scaling table of BENCHMARKS.md (issue 18). For the
# Happy Buddha (100k triangles) and the lab grids of it (scenes/bench/buddha-grid-{1m,3m,10m}),
# and a single 10M-triangle OBJ written from the same mesh, renders 1024x768 Whitted twice with
# an empty prepared-scene cache: the first run loads, builds and stores, the second maps the
# entry. Prints one Markdown row per run: load, BVH build (tree part), upload, render, wall.
# With --one-core the first runs are repeated under `taskset -c 0` (the build on one thread).
#
#   tools/bench-big-scenes.sh [--vkrt PATH] [--one-core] [--skip-obj]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
vkrt="$root/target/release/vkrt" one_core=0 skip_obj=0
while [ $# -gt 0 ]; do
  case "$1" in
    --vkrt) vkrt=$2; shift 2 ;;
    --one-core) one_core=1; shift ;;
    --skip-obj) skip_obj=1; shift ;;
    -h|--help) sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "bench-big-scenes: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
buddha="$root/../shared/scenes/happy-buddha-100k/buddha.obj"
[ -f "$buddha" ] || { echo "bench-big-scenes: needs $buddha (../shared)" >&2; exit 2; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
scenes=("$buddha" "$root/scenes/bench/buddha-grid-1m.yaml" "$root/scenes/bench/buddha-grid-3m.yaml" "$root/scenes/bench/buddha-grid-10m.yaml")
if [ $skip_obj = 0 ]; then
  # One OBJ file with the 100 copies of the 10M grid (406 MB): what a big export looks like.
  python3 - "$buddha" "$tmp/buddha-grid-10m.obj" <<'PY'
import sys
src, out = sys.argv[1], sys.argv[2]
lines = open(src).read().splitlines()
verts = [tuple(map(float, l.split()[1:4])) for l in lines if l.startswith('v ')]
faces = [[int(c.split('/')[0]) for c in l.split()[1:]] for l in lines if l.startswith('f ')]
with open(out, 'w') as f:
    for k in range(100):
        dx, dz = (k % 10) * 4.5, (k // 10) * 4.5
        f.write(''.join(f'v {x + dx:.6f} {y:.6f} {z + dz:.6f}\n' for x, y, z in verts))
    for k in range(100):
        o = k * len(verts)
        f.write(''.join('f ' + ' '.join(str(i + o) for i in t) + '\n' for t in faces))
PY
  scenes+=("$tmp/buddha-grid-10m.obj")
fi
echo "vkrt big scenes, $(date -u +%Y-%m-%d), CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores$(cd "$root" && git rev-parse --short HEAD 2>/dev/null | sed 's/^/, commit /')"
echo
echo "| scene | triangles | run | load s | BVH build s (tree) | upload s | render s | wall s |"
echo "|---|---:|---|---:|---:|---:|---:|---:|"
row() { # scene run-label [taskset...]
  local scene=$1 label=$2; shift 2
  local start end log
  start=$(date +%s.%N)
  log=$("$@" "$vkrt" render "$scene" --width 1024 --height 768 -v --cache "$tmp/cache" -o "$tmp/out.png" 2>&1)
  end=$(date +%s.%N)
  local tris load build tree upload render
  tris=$(grep -o '[0-9]* triangles' <<<"$log" | head -1 | cut -d' ' -f1)
  local line; line=$(grep '^load ' <<<"$log" | head -1)
  load=$(sed -n 's/^load \([0-9.]*\) s.*/\1/p' <<<"$line")
  build=$(sed -n 's/.*BVH build \([0-9.]*\) s.*/\1/p' <<<"$line")
  tree=$(sed -n 's/.*tree \([0-9.]*\) on.*/\1/p' <<<"$line")
  upload=$(sed -n 's/.*upload \([0-9.]*\) s.*/\1/p' <<<"$line")
  render=$(sed -n 's/.* in \([0-9.]*\) s on .*/\1/p' <<<"$log" | tail -1)
  [ -n "$build" ] && build="$build ($tree)" || build="- (cached)"
  echo "| $(basename "$scene") | $tris | $label | $load | $build | $upload | $render | $(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f", b - a }') |"
}
for scene in "${scenes[@]}"; do
  rm -rf "$tmp/cache"
  if [ $one_core = 1 ]; then
    row "$scene" "first, 1 core" taskset -c 0
    rm -rf "$tmp/cache"
  fi
  row "$scene" "first" env
  row "$scene" "cached" env
done
