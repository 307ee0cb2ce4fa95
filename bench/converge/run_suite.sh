#!/usr/bin/env bash
# The converge suite: every scene of bench/converge/scenes/ and RayON's colour-bleed box
# through `tessera-bench converge`, one CSV, plot and log per scene, and OUTDIR/summary.md
# with the time to relMSE 1e-3 of each renderer, how the two references compare and the
# fits' slopes (one flatter than -0.8 is marked: its extrapolation is unreliable).
#
#   bench/converge/run_suite.sh OUTDIR [--peer cycles] [--reference-spp N] [--spp LIST]
#                               [--threads N] [--build DIR] [--adaptive TARGETS] [--denoise]
#
# --adaptive and --denoise add Tessera's adaptive-sampling and denoised series (see
# `tessera-bench converge --help`) and their times to the summary.
# Defaults: reference 4096 spp, spp 1,2,...,256, 2 threads, build/. Scenes that need
# ../shared (RayON's scenes, the 250k-triangle mesh) are skipped when it is absent.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
shared="$root/../shared"

if [ $# -lt 1 ] || [[ "$1" == -* ]]; then
  sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi
out=$1
shift
peer=()
extra=()
reference_spp=4096
spp=1,2,4,8,16,32,64,128,256
threads=2
build="$root/build"
while [ $# -gt 0 ]; do
  case "$1" in
    --peer) peer=(--peer "$2"); shift 2 ;;
    --reference-spp) reference_spp=$2; shift 2 ;;
    --spp) spp=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    --adaptive) extra+=(--adaptive "$2"); shift 2 ;;
    --denoise) extra+=(--denoise); shift ;;
    *) echo "run_suite.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
bench="$build/bench/accel/tessera-bench"
[ -x "$bench" ] || { echo "run_suite.sh: $bench not built (cmake --build $build --target tessera-bench)" >&2; exit 1; }
mkdir -p "$out/scenes"

# The emissive grid is generated, not committed: the scene is copied beside it.
cp "$here/scenes/emissive_triangles.yaml" "$out/scenes/"
/usr/bin/python3 "$here/scenes/make_emissive_grid.py" "$out/scenes/emissive_grid.obj"

scenes=(
  "color_bleed_box=$shared/rayon-scenes/09_color_bleed_box.yaml"
  "two_lights=$here/scenes/two_lights.yaml"
  "glossy_glass=$here/scenes/glossy_glass.yaml"
  "emissive_triangles=$out/scenes/emissive_triangles.yaml"
  "mesh_250k=$here/scenes/mesh_250k.yaml"
  "lights_and_sky=$here/scenes/lights_and_sky.yaml"
  "daylight_room=$here/scenes/daylight_room.yaml"
  "many_lights=$here/scenes/many_lights.yaml"
  "textured=$here/scenes/textured.yaml"
  # RayON's own scenes, beside the box: none of the suite's tuning looked at them.
  "rayon_01=$shared/rayon-scenes/01_bvh_test_scene.yaml"
  "rayon_06=$shared/rayon-scenes/06_caustics_chapel.yaml"
)

summary="$out/summary.md"
{
  echo "# Converge suite"
  echo
  echo "$(date -u '+%Y-%m-%d %H:%M UTC'), $(uname -n), $threads threads, reference $reference_spp spp, spp $spp${peer:+, peer ${peer[1]}}."
  echo "Times are seconds to relMSE 1e-3 against each renderer's own reference, measured or extrapolated (see each scene's .log); \"–\": not reached and not falling."
  echo
  echo "A slope (relMSE ~ time^slope over the later renders) flatter than -0.8 is marked \"!\": its extrapolation is unreliable (fireflies not yet averaged, bias or a noisy reference; see the scene's .log), and the last column gives the ratio of the times the last renders predict at slope -1."
  echo
  echo "| scene | Tessera time to 1e-3 | Cycles time to 1e-3 | Cycles / Tessera | Tessera reference mean | Cycles reference mean | relMSE between references | Tessera adaptive | Tessera denoised | slopes, Tessera / Cycles | Cycles / Tessera at slope -1 |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|"
} > "$summary"

for entry in "${scenes[@]}"; do
  name=${entry%%=*}
  scene=${entry#*=}
  if [ "$name" = mesh_250k ] && [ ! -f "$shared/meshes/suzanne-sub4.ply" ] || [ ! -f "$scene" ]; then
    echo "run_suite.sh: $name skipped ($scene or its mesh is absent)"
    echo "| $name | skipped | | | | | | | | | |" >> "$summary"
    continue
  fi
  echo "run_suite.sh: $name"
  # Every scene at the suite's size, whatever its file says.
  nice "$bench" converge "$scene" --width 128 --height 128 --threads "$threads" \
    --reference-spp "$reference_spp" --spp "$spp" ${peer[@]+"${peer[@]}"} ${extra[@]+"${extra[@]}"} \
    --csv "$out/$name.csv" --plot "$out/$name.png" --save-reference "$out/${name}_reference.exr" \
    --peer-dir "$out/${name}_cycles" | tee "$out/$name.log"
  line=$(grep '^summary:' "$out/$name.log")
  slopes=$(grep '^summary_slopes:' "$out/$name.log")
  field() { sed -n "s/.* $1=\([^ ]*\).*/\1/p" <<< " $line"; }
  slope_field() { sed -n "s/.* $1=\([^ ]*\).*/\1/p" <<< " $slopes"; }
  fmt() { [ "$1" = nan ] && echo "–" || printf '%.3g' "$1"; }
  slope() {  # a renderer's slope, "!" where converge flagged its fit as too flat to trust
    local value
    value=$(slope_field "$1_slope")
    [ -z "$value" ] || [ "$value" = nan ] && { echo "–"; return; }
    printf '%.2f%s' "$value" "$([ "$(slope_field "$1_shallow")" = 1 ] && echo " !")"
  }
  echo "| $name | $(fmt "$(field tessera_time)") | $(fmt "$(field cycles_time)") | $(fmt "$(field ratio)") | $(fmt "$(field tessera_ref_mean)") | $(fmt "$(field cycles_ref_mean)") | $(fmt "$(field ref_relmse)") | $(fmt "$(field adaptive_time)") | $(fmt "$(field denoised_time)") | $(slope tessera) / $(slope cycles) | $(fmt "$(slope_field ratio_unit_slope)") |" >> "$summary"
done
# What the peer drew differently from Tessera, as it said: a ratio or a pair of means is read
# with these in mind.
{
  echo
  echo "Peer warnings (what the Cycles peer does not draw as Tessera does; bench/peers/README.md):"
  found=0
  for entry in "${scenes[@]}"; do
    name=${entry%%=*}
    [ -f "$out/$name.log" ] || continue
    while IFS= read -r warning; do
      echo "- $name: ${warning#cycles_render.py: warning: }"
      found=1
    done < <(grep '^cycles_render.py: warning:' "$out/$name.log" | sort -u)
  done
  [ "$found" = 1 ] || echo "- none"
} >> "$summary"
echo "run_suite.sh: $summary"
cat "$summary"
