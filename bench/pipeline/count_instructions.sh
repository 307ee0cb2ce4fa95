#!/usr/bin/env bash
# Instruction counts (callgrind) of the three renderers on each benchmark scene: repeatable
# on a busy machine, where wall times are not. Usage: count_instructions.sh BUILD_DIR [W H SPP]
set -euo pipefail
bench="${1:-build}/bench/pipeline/tessera-bench-specialise"
size=(--width "${2:-64}" --height "${3:-48}" --spp "${4:-2}")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
count() {
  # Only the rendering counts: scene generation, BVH builds and start-up are left out.
  valgrind --tool=callgrind --toggle-collect="*render_all*" --callgrind-out-file="$tmp/out" "$bench" "${size[@]}" --scene "$1" --only "$2" \
    >/dev/null 2>"$tmp/log"
  grep -o "Collected : [0-9]*" "$tmp/log" | grep -o "[0-9]*"
}
log_all=0; log_virtual=0; n=0; n_virtual=0
for scene in triangles analytic mixed triangles_sky; do
  s=$(count "$scene" specialised); a=$(count "$scene" all); v=$(count "$scene" virtual)
  printf 'scene=%-14s specialised_Ir=%s all_features_Ir=%s virtual_Ir=%s ratio_all=%.3f ratio_virtual=%.3f\n' \
    "$scene" "$s" "$a" "$v" "$(echo "$a/$s" | bc -l)" "$(echo "$v/$s" | bc -l)"
  log_all=$(echo "$log_all + l($a/$s)" | bc -l); n=$((n + 1))
  # The virtual baseline sits out scenes it cannot render (0 instructions): left out of its mean.
  if [ "${v:-0}" -gt 0 ]; then
    log_virtual=$(echo "$log_virtual + l($v/$s)" | bc -l); n_virtual=$((n_virtual + 1))
  fi
done
printf 'instructions_vs_all_features=%.3f instructions_vs_virtual=%.3f\n' \
  "$(echo "e($log_all/$n)" | bc -l)" "$(echo "e($log_virtual/$n_virtual)" | bc -l)"
