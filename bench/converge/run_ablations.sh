#!/usr/bin/env bash
# Tessera's estimator switches, one at a time, on scenes of a finished suite run: each
# variant's time to relMSE 1e-3 against the suite's own Tessera reference (rendered with
# every default on: Sobol sampler, MIS, light tree), as a markdown table.
#
#   bench/converge/run_ablations.sh SUITE_OUTDIR [--build DIR] [--threads N] [--spp LIST]
#
# SUITE_OUTDIR is the folder bench/converge/run_suite.sh wrote (it holds the references and
# the generated emissive-triangle scene).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
shared="$root/../shared"
[ $# -ge 1 ] || { sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
suite=$1
shift
build="$root/build"
threads=2
spp=1,2,4,8,16,32,64,128,256
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --spp) spp=$2; shift 2 ;;
    *) echo "run_ablations.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
bench="$build/bench/accel/tessera-bench"
scenes=(
  "color_bleed_box=$shared/rayon-scenes/09_color_bleed_box.yaml"
  "two_lights=$here/scenes/two_lights.yaml"
  "glossy_glass=$here/scenes/glossy_glass.yaml"
  "emissive_triangles=$suite/scenes/emissive_triangles.yaml"
)
variants=(
  "default="
  "independent sampler=--sampler independent"
  "light sampling only=--light-strategy light"
  "BSDF sampling only=--light-strategy bsdf"
  "no light tree=--no-light-tree"
)
out="$suite/ablations"
mkdir -p "$out"
header="| scene |"
rule="|---|"
for v in "${variants[@]}"; do header+=" ${v%%=*} |"; rule+="---|"; done
table="$header"$'\n'"$rule"
for entry in "${scenes[@]}"; do
  name=${entry%%=*}
  scene=${entry#*=}
  reference="$suite/${name}_reference.exr"
  if [ ! -f "$scene" ] || [ ! -f "$reference" ]; then
    echo "run_ablations.sh: $name skipped (no scene or no reference in $suite)"
    continue
  fi
  row="| $name |"
  for v in "${variants[@]}"; do
    label=${v%%=*}
    read -r -a flags <<< "${v#*=}"
    log="$out/${name}_${label// /_}.log"
    nice "$bench" converge "$scene" --width 128 --height 128 --threads "$threads" \
      --reference "$reference" --spp "$spp" ${flags[@]+"${flags[@]}"} > "$log"
    time=$(sed -n 's/.*tessera_time=\([^ ]*\).*/\1/p' "$log")
    [ -n "$time" ] || time=$(sed -n 's/^time to relMSE [^:]*: \([^ ]*\) s.*/\1/p' "$log")
    row+=" ${time:-–} |"
    echo "run_ablations.sh: $name, $label: ${time:-–} s"
  done
  table+=$'\n'"$row"
done
echo "$table" | tee "$out/ablations.md"
