#!/usr/bin/env bash
# Issue 15's GPU checks in one call on a lent GPU machine (see README.md beside this file):
# the GPU unit tests (CPU-GPU image agreement, batches, the ray tracer's hits), Mrays/s of
# primary and diffuse rays on suzanne-sub5 (GPU, both BVH walks, against this machine's CPU),
# the Cornell box's samples per second and time to relMSE 1e-3 on the GPU and on the CPU, and
# how tesserad splits a mixed job's tiles at three GPU batch sizes. Run from the repository root with .devicepack
# carried (bench/gpu/pack_for_device.sh makes it). Takes 3-6 minutes; each step has its own
# time limit so one stuck step cannot eat the lease. Logs go to $OUT (at most 8 files);
# the summary is printed last.
#
# QUICK=1 shrinks every step, to try the script itself on a machine without a GPU;
# PACKED_GLIBC=1 runs the programs under the packed glibc even where this one is as new.
set -uo pipefail

root="$(pwd)"
out="${OUT:-/tmp/tessera-gpu-out}"
mkdir -p "$out"
work=/tmp/tessera-gpu
rm -rf "$work" && mkdir -p "$work"
log="$out/device_checks.log"
summary="$out/summary.txt"
: >"$summary"
say() { echo "$*" | tee -a "$summary"; }
step() { echo "== $(date -u +%H:%M:%S) $*" | tee -a "$log"; }

tar -C "$work" -xJf "$root/.devicepack/pack.tar.xz" || { echo "no .devicepack/pack.tar.xz (carry it)"; exit 2; }
export LD_LIBRARY_PATH="$work/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
bin="$work/bin"
# Built on Debian bookworm: where this machine's glibc is older, each program runs under the
# packed glibc and its loader, the driver's libraries still found where they are installed.
host_glibc="$(ldd --version 2>/dev/null | head -1 | awk '{print $NF}')"
if [ "${PACKED_GLIBC:-0}" = 1 ] || [ "$(printf '%s\n%s\n' "$(cat "$work/glibc_version")" \
  "$host_glibc" | sort -V | head -1)" != "$(cat "$work/glibc_version")" ]; then
  echo "glibc $host_glibc here, older than the pack's $(cat "$work/glibc_version"): using the packed one"
  for program in "$work"/bin/*; do
    mv "$program" "$program.real"
    printf '#!/bin/sh\nexec %s --library-path %s "%s" "$@"\n' "$work/lib/glibc/ld-linux-x86-64.so.2" \
      "$work/lib:$work/lib/glibc:/usr/local/nvidia/lib64:/usr/lib/x86_64-linux-gnu:/usr/lib64" \
      "$program.real" >"$program"
    chmod +x "$program"
  done
fi
threads="$(nproc)"
if [ "${QUICK:-0}" = 1 ]; then
  series=1,2,4,8 largest=8 size=(--width 160 --height 120 --spp 8) ray_size=(--width 128 --height 128)
else
  series=1,2,4,8,16,32,64,128,256,512,1024 largest=1024
  size=(--width 1280 --height 960 --spp 256) ray_size=(--width 1024 --height 1024)
fi
# The tests read examples/ by the path of the checkout they were built from.
source_dir="$(cat "$work/source_dir")"
if [ ! -e "$source_dir" ]; then mkdir -p "$(dirname "$source_dir")" && ln -s "$root" "$source_dir"; fi

step "machine"
{
  nvidia-smi --query-gpu=name,memory.total,clocks.sm,clocks.max.sm,driver_version --format=csv
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2) x $threads"
  echo "pack built at commit $(cat "$work/commit"); tree at $(git -C "$root" rev-parse --short HEAD 2>/dev/null)"
  for program in tessera-bench tesserad tessera; do
    "$bin/$program" --help >/dev/null 2>&1 || echo "CANNOT RUN $program: $("$bin/$program" --help 2>&1 | head -3)"
  done
} 2>&1 | tee -a "$log"
say "device: $(nvidia-smi --query-gpu=name --format=csv,noheader | head -1), cpu threads: $threads, pack commit $(cat "$work/commit")"

step "unit_gpu"
timeout 240 "$bin/unit_gpu" --gtest_color=no 2>&1 | tee "$work/unit_gpu.log" >>"$log"
say "unit_gpu: $(grep -E '^\[  (PASSED|FAILED|SKIPPED) +\] [0-9]+ tests?' "$work/unit_gpu.log" | tr '\n' ' ')"
grep -E '^(cpu-gpu|kernel) ' "$work/unit_gpu.log" | tee -a "$summary"

mesh="$work/data/suzanne-sub5.ply"
if [ -f "$mesh" ]; then
  for kind in primary diffuse; do
    step "rays $kind"
    timeout 120 "$bin/tessera-bench" rays --mesh "$mesh" --kind $kind "${ray_size[@]}" \
      --out "$work/$kind.rays" >>"$log" 2>&1
    step "gpu-trace $kind"
    timeout 180 "$bin/tessera-bench" gpu-trace --mesh "$mesh" --rays "$work/$kind.rays" \
      --threads "$threads" --repeat 5 2>&1 | tee "$work/trace-$kind.log" >>"$log"
    say "suzanne-sub5 $kind: $(tail -1 "$work/trace-$kind.log")"
  done
else
  say "suzanne-sub5: not in the pack; ray benchmarks skipped"
fi

scene="$root/examples/scenes/cornell.yaml"
reference="$work/data/cornell-reference-4096.exr"
for device in gpu cpu; do
  step "converge $device"
  timeout 200 "$bin/tessera-bench" converge "$scene" --reference "$reference" \
    --spp $series --threads "$threads" --device $device \
    --csv "$out/converge_$device.csv" 2>&1 | tee "$work/converge-$device.log" >>"$log"
  # samples per second at the largest count: pixels x spp / render seconds
  pixels="$(sed -n 's/^scene: .*, \([0-9]*\)x\([0-9]*\),.*/\1 \2/p' "$work/converge-$device.log" | awk '{print $1 * $2}')"
  rate="$(awk -v p="${pixels:-0}" -v largest=$largest '$1 == largest && NF == 8 {printf "%.3g", p * $1 / $3}' "$work/converge-$device.log")"
  say "cornell $device: ${rate:-?} samples/s at $largest spp; $(grep -m1 'time to relMSE 0.001:' "$work/converge-$device.log")"
done

# One daemon per GPU batch size (gpu_batch_pixels; 0: the device's own, multiprocessors x
# 1,024): the default renders the job on any device, the GPU alone and the CPU alone; the
# others only on any, to see how the batch size moves the split and the time.
run_daemon() {
  local batch=$1
  shift
  step "tesserad, gpu_batch_pixels $batch: devices $*"
  local port=50151 metrics_port=9464 daemon_log="$work/tesserad-$batch.log"
  TESSERAD_GPU_BATCH_PIXELS=$batch "$bin/tesserad" --listen 127.0.0.1:$port --threads "$threads" \
    --data "$work/var-$batch" --log-format json --metrics-listen 127.0.0.1:$metrics_port \
    >"$daemon_log" 2>&1 &
  local daemon=$!
  for _ in $(seq 1 50); do "$bin/tessera" health --server 127.0.0.1:$port >/dev/null 2>&1 && break; sleep 0.2; done
  "$bin/tessera" version --server 127.0.0.1:$port 2>&1 | tee -a "$log"
  for spec in "$@"; do
    # DEVICE or DEVICE:denoise (the job then asks for the denoiser's AOVs)
    local device=${spec%%:*} extra=()
    [ "$spec" != "$device" ] && extra=(--denoise)
    sed "s/^render:/render:\n  device: $device/" "$scene" >"$work/cornell-$device.yaml"
    local start rc completed before
    before=$(grep -c '"event":"job_completed"' "$daemon_log")
    start=$(date +%s.%N)
    timeout 150 "$bin/tessera" render "$work/cornell-$device.yaml" -o "$work/mixed-$device.exr" \
      --server 127.0.0.1:$port "${size[@]}" "${extra[@]}" >>"$log" 2>&1
    rc=$?
    completed="no job_completed line: $(tail -n 1 "$log")"
    if [ "$(grep -c '"event":"job_completed"' "$daemon_log")" -gt "$before" ]; then
      completed="$(grep -o '"event":"job_completed".*' "$daemon_log" | tail -1 | grep -o '"tiles_rendered_by":"[^"]*"')"
    fi
    say "cornell ${size[*]} ${extra[*]}, device $device, gpu_batch_pixels $batch: rc $rc, $(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN {printf "%.2f", b - a}') s wall, $completed"
  done
  python3 - "$metrics_port" >"$work/metrics-$batch.txt" 2>&1 <<'PY'
import sys, urllib.request
print(urllib.request.urlopen(f"http://127.0.0.1:{sys.argv[1]}/metrics", timeout=5).read().decode())
PY
  grep -E '^tessera_(tiles_rendered_by_device|device_fallbacks)_total' "$work/metrics-$batch.txt" | tee -a "$summary"
  kill $daemon
  wait $daemon 2>/dev/null
  cat "$daemon_log" >>"$out/tesserad.log"
}
run_daemon 0 any gpu cpu gpu:denoise
run_daemon 32768 any
run_daemon 524288 any

cp "$work/unit_gpu.log" "$out/unit_gpu.log" 2>/dev/null
echo
echo "==== summary"
cat "$summary"
