#!/usr/bin/env bash
# Usage: tools/identity/check.sh OLD_VKRT NEW_VKRT [OUTDIR]: renders, traces and BVH tables of
# both binaries on the same inputs; lists the files that differ. See README.md beside it.
set -u
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
old=${1:?usage: check.sh OLD_VKRT NEW_VKRT [OUTDIR]}; new=${2:?usage: check.sh OLD_VKRT NEW_VKRT [OUTDIR]}
out=${3:-$root/target/identity}
S=$root/../shared/scenes; M=$root/scenes
[ -d "$S" ] || { echo "check.sh: needs $S (the shared test data)" >&2; exit 1; }
mkdir -p "$out/rays"
python3 "$here/rays.py" "$out/rays/cornell.npy" 100000 0 550 1
python3 "$here/rays.py" "$out/rays/sponza.npy" 200000 -8 8 2
python3 "$here/rays.py" "$out/rays/conference.npy" 200000 -300 600 3

run() { # run BINARY DIR
  local B=$1 O=$2; mkdir -p "$O"
  local LAYOUTS="threaded multi-order parent-link compact wide"
  declare -A SC=(
   [labcornell]=$M/lab/cornell_box/cornell_box.yaml [measured]=$M/cornell-measured/cornell.yaml
   [boxpath]=$M/lab/Box_ver_path/Box_ver_path.yaml [oak]=$S/lab/white_oak/white_oak.yaml
   [sphere]=$S/cornell-box/CornellBox-Sphere.obj [mirror]=$S/cornell-box/CornellBox-Mirror.obj
   [glossy]=$S/cornell-box/CornellBox-Glossy.obj [sponza]=$S/sponza-dabrovic/sponza.obj)
  for s in "${!SC[@]}"; do
    for l in $LAYOUTS; do
      "$B" render "${SC[$s]}" -o "$O/w-$s-$l.pfm" --width 96 --height 80 --spp 2 --layout $l 2>/dev/null || echo "FAIL whitted $s $l"
      "$B" render "${SC[$s]}" -o "$O/p-$s-$l.pfm" --width 64 --height 48 --spp 8 --layout $l --integrator path 2>/dev/null || echo "FAIL path $s $l"
    done
  done
  local m=${SC[measured]} p="--width 64 --height 64 --integrator path"
  local -a sets=(
    "adaptive|$m $p --spp 16 --adaptive" "coh8|$m $p --spp 8 --coherence 8" "indep|$m $p --spp 8 --sampler independent"
    "strat|$m $p --spp 8 --sampler stratified" "nonee|$m $p --spp 8 --no-nee" "depth3|$m $p --spp 8 --max-depth 3 --seed 5"
    "sky|${SC[sponza]} $p --spp 4 --sky 1,1,1" "allfeat|${SC[oak]} $p --spp 4 --all-features"
    "wallfeat|${SC[oak]} --width 64 --height 64 --all-features" "median|$m --width 64 --height 64 --builder median"
    "sweep|$m --width 64 --height 64 --builder sweep-sah" "reins|$m --width 64 --height 64 --builder reinsertion")
  for e in "${sets[@]}"; do
    # shellcheck disable=SC2086
    "$B" render ${e#*|} -o "$O/x-${e%%|*}.pfm" 2>/dev/null || echo "FAIL ${e%%|*}"
  done
  "$B" render "$m" -o "$O/x-png.png" --width 64 --height 64 2>/dev/null || echo FAIL png
  "$B" render "$m" -o "$O/x-exr.exr" --width 64 --height 64 2>/dev/null || echo FAIL exr
  local c="--width 48 --height 48 --integrator path"
  "$B" render "$m" -o "$O/m1.pfm" $c --spp 4 --seed 1 --checkpoint "$O/m1.ckpt" 2>/dev/null || echo FAIL ckpt
  "$B" render "$m" -o "$O/m2.pfm" $c --spp 4 --seed 2 --checkpoint "$O/m2.ckpt" 2>/dev/null || echo FAIL ckpt
  "$B" render "$m" -o "$O/m1r.pfm" $c --spp 8 --seed 1 --resume "$O/m1.ckpt" 2>/dev/null || echo FAIL resume
  "$B" merge "$O/m1.ckpt" "$O/m2.ckpt" -o "$O/merged.pfm" 2>/dev/null || echo FAIL merge
  declare -A RS=([measured]=$out/rays/cornell.npy [sponza]=$out/rays/sponza.npy)
  local strip='s/: [0-9.]+ M rays\/s.*build [0-9]+ ms not counted[^)]*\)//'
  for s in measured sponza; do
    for l in $LAYOUTS; do
      for a in "" "--any-hit"; do
        for ord in given sorted; do
          local n=$O/t-$s-$l$a-$ord.npy
          # shellcheck disable=SC2086
          "$B" trace "${SC[$s]}" --rays "${RS[$s]}" --out "$n" --layout $l $a --order $ord 2>"$n.log" || echo "FAIL trace $s $l"
          sed -E "$strip" "$n.log" > "$n.txt"; rm "$n.log"
        done
      done
    done
  done
  "$B" trace "$S/conference/conference.obj" --rays "$out/rays/conference.npy" --out "$O/t-conf.npy" --builder reinsertion 2>"$O/t-conf.log"
  sed -E "$strip" "$O/t-conf.log" > "$O/t-conf.txt"; rm "$O/t-conf.log"
  # Drop the timing columns (build_ms, *_mrays); keep names, sizes, SAH and per-ray counters.
  "$B" bvh "$m" "${SC[sphere]}" --format csv --width 64 --height 64 --repeat 1 2>/dev/null | cut -d, -f1-4,6-10,12-13,15-16 > "$O/bvh.csv"
}

run "$old" "$out/old"
run "$new" "$out/new"
n=0; d=0
for f in $(cd "$out/old" && ls); do
  n=$((n + 1))
  if ! cmp -s "$out/old/$f" "$out/new/$f"; then echo "differs: $f"; d=$((d + 1)); fi
done
for f in $(cd "$out/new" && ls); do [ -e "$out/old/$f" ] || { echo "only in new: $f"; d=$((d + 1)); }; done
echo "$n files, $d differ ($out/old vs $out/new)"
