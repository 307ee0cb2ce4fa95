#!/usr/bin/env bash
# Cost per sample of two builds of the `tessera` CLI (issue 10's bound: a newer path tracer
# against the one before the light transport work, f05944b, built beside it), on the scenes
# the README's figures use: the render time the CLI reports at SPP samples less the time at
# 1 sample (so start-up and image writing drop out), 128x128, max depth 6, pinned to one CPU,
# the two binaries alternating. Prints every run, then medians, minima and their ratios.
#
#   bench/converge/per_sample_cost.sh OLD_TESSERA NEW_TESSERA [ROUNDS (6)] [SPP (128)]
#
# ALL=1 adds the other converge scenes the old binary can read (rough_materials, mesh_250k,
# many_lights and emissive_triangles, whose 1,024-triangle grid is generated into a temporary
# folder); a scene either binary cannot render is skipped with a note.
#
# Wall clock on a shared machine is noisy; callgrind instruction counts of render_tile are the
# repeatable figure (see the README's "Cost per sample" paragraph for that command).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
[ $# -ge 2 ] || { sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
old=$1 new=$2 rounds=${3:-6} spp=${4:-128}
box="$root/../shared/rayon-scenes/09_color_bleed_box.yaml"
scenes=("$root/bench/converge/scenes/glossy_glass.yaml" "$root/bench/converge/scenes/two_lights.yaml")
[ -f "$box" ] && scenes=("$box" "${scenes[@]}")
cpu=$(($(nproc) - 1))
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
if [ "${ALL:-0}" = 1 ]; then
  mkdir -p "$out/scenes"
  cp "$root/bench/converge/scenes/emissive_triangles.yaml" "$out/scenes/"
  /usr/bin/python3 "$root/bench/converge/scenes/make_emissive_grid.py" \
    "$out/scenes/emissive_grid.obj" > /dev/null
  for scene in "$root/bench/converge/scenes/rough_materials.yaml" \
    "$root/bench/converge/scenes/mesh_250k.yaml" "$root/bench/converge/scenes/many_lights.yaml" \
    "$out/scenes/emissive_triangles.yaml"; do
    if "$old" render --local --threads 1 --width 16 --height 16 --spp 1 "$scene" \
      -o "$out/probe.exr" > /dev/null 2>&1 &&
      "$new" render --local --threads 1 --width 16 --height 16 --spp 1 "$scene" \
        -o "$out/probe.exr" > /dev/null 2>&1; then
      scenes+=("$scene")
    else
      echo "skipped $(basename "$scene" .yaml): a binary cannot render it" >&2
    fi
  done
fi

# The seconds the CLI reports for one local render.
render_seconds() {
  taskset -c "$cpu" "$1" render --local --threads 1 --width 128 --height 128 --max-depth 6 \
    --spp "$2" "$3" -o "$out/image.exr" 2>&1 | sed -n 's/.* in \([0-9.]*\) s,.*/\1/p' | tail -1
}

for round in $(seq "$rounds"); do
  for scene in "${scenes[@]}"; do
    for which in old new; do
      bin=$old
      [ "$which" = new ] && bin=$new
      many=$(render_seconds "$bin" "$spp" "$scene")
      one=$(render_seconds "$bin" 1 "$scene")
      per=$(awk -v a="$many" -v b="$one" 'BEGIN { printf "%.3f", a - b }')
      echo "$round $(basename "$scene" .yaml) $which $per" | tee -a "$out/runs"
    done
  done
done

echo "scene old_median new_median median_ratio old_min new_min min_ratio"
for scene in "${scenes[@]}"; do
  name=$(basename "$scene" .yaml)
  stats() {  # median and minimum of one binary's per-sample times
    awk -v s="$name" -v w="$1" '$2 == s && $3 == w { print $4 }' "$out/runs" | sort -n |
      awk '{ v[NR] = $1 } END { m = NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2;
                               print m, v[1] }'
  }
  read -r old_median old_min < <(stats old)
  read -r new_median new_min < <(stats new)
  awk -v n="$name" -v om="$old_median" -v nm="$new_median" -v on="$old_min" -v nn="$new_min" \
    'BEGIN { printf "%s %.3f %.3f %.2f %.3f %.3f %.2f\n", n, om, nm, nm / om, on, nn, nn / on }'
done
