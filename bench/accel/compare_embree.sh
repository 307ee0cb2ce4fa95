#!/bin/bash
# Runs the tracing comparison against Embree the project reports: suzanne-sub5 and two
# generated meshes of at least 500k triangles, primary and diffuse rays, 1 thread and all
# threads, against Embree built at medium and at high quality (build times and memory
# next to trace speed; the load average after each run). Usage:
# bench/accel/compare_embree.sh BUILD_DIR [SHARED_MESH_DIR]
# Ray files and generated meshes go to BUILD_DIR/accel-data (made once, then reused).
set -euo pipefail
build=${1:?usage: compare_embree.sh BUILD_DIR [SHARED_MESH_DIR]}
shared=${2:-$(dirname "$0")/../../../shared/meshes}
bench=$build/bench/accel/tessera-bench
compare=$build/bench/accel/embree_compare
data=$build/accel-data
threads_all=$(nproc)
mkdir -p "$data"
[ -f "$data/knot.ply" ] || "$bench" mesh --shape knot --triangles 800000 --out "$data/knot.ply"
[ -f "$data/scatter.ply" ] || "$bench" mesh --shape scatter --triangles 600000 --out "$data/scatter.ply"
declare -A meshes=([sub5]="$shared/suzanne-sub5.ply" [knot]="$data/knot.ply" [scatter]="$data/scatter.ply")
for name in sub5 knot scatter; do
  mesh=${meshes[$name]}
  for kind in primary diffuse; do
    rays=$data/$name-$kind.rays
    [ -f "$rays" ] || "$bench" rays --mesh "$mesh" --kind $kind --width 1024 --height 1024 --out "$rays"
    for threads in 1 "$threads_all"; do
      echo "== $name $kind, $threads thread(s): $compare --mesh $mesh --rays $rays --threads $threads --repeat 5"
      "$compare" --mesh "$mesh" --rays "$rays" --threads "$threads" --repeat 5 | tail -n +2
      uptime
    done
  done
done
