#!/usr/bin/env bash
# Packs what bench/gpu/device_checks.sh needs on a lent GPU machine, which has nvcc and the
# NVIDIA driver but none of Tessera's libraries (gRPC, yaml-cpp, assimp, TBB...) and no
# network: the GPU build's programs, every shared library they load that is not glibc's or
# the driver's, the benchmark mesh and a CPU reference of the Cornell box. One xz archive,
# small enough for the device tool's 64 MiB working-tree limit.
#
#   bash bench/gpu/pack_for_device.sh [BUILD_CUDA] [SHARED_MESHES]
#
# BUILD_CUDA (default build-cuda) must be configured with -DTESSERA_CUDA=ON; the programs are
# built here if they are not. Writes .devicepack/pack.tar.xz (git-ignored); then:
#   device run: command "bash bench/gpu/device_checks.sh", carry [".devicepack"]
set -euo pipefail

root="$(cd "$(dirname "$0")/../.." && pwd)"
build="${1:-$root/build-cuda}"
meshes="${2:-$root/../shared/meshes}"
pack="$root/.devicepack"
stage="$(mktemp -d)"
trap 'rm -rf "$stage"' EXIT

# A GPU build: TESSERA_CUDA not OFF, and CMake found nvcc (ON requires it, AUTO looks).
if grep -q '^TESSERA_CUDA:STRING=OFF' "$build/CMakeCache.txt" 2>/dev/null ||
  ! grep -q '^CMAKE_CUDA_COMPILER:[A-Z]*=.' "$build/CMakeCache.txt" 2>/dev/null; then
  echo "pack_for_device: $build is not a GPU build; configure it with" \
    "cmake -S $root -B $build -DCMAKE_BUILD_TYPE=Release -DTESSERA_CUDA=ON" >&2
  exit 2
fi
cmake --build "$build" -j"$(nproc)" --target tessera-bench unit_gpu tesserad tessera

mkdir -p "$stage/bin" "$stage/lib" "$stage/data"
programs=("$build/bench/accel/tessera-bench" "$build/tests/unit_gpu" "$build/server/tesserad"
  "$build/client/tessera")
for program in "${programs[@]}"; do
  cp "$program" "$stage/bin/"
  strip --strip-unneeded "$stage/bin/$(basename "$program")"
done

# Every library travels but the driver's, libstdc++ included, so the programs find the
# versions they were linked against. glibc's go to lib/glibc, used (with its loader) only
# where the device machine's glibc is older than this one's.
mkdir -p "$stage/lib/glibc"
for program in "${programs[@]}"; do
  ldd "$program" | awk '$2 == "=>" && $3 ~ /^\// {print $3} $1 ~ /^\/.*ld-linux/ {print $1}'
done | sort -u | while read -r library; do
  case "$(basename "$library")" in
    libcuda.so.* | libnvidia-*) ;;
    libc.so.* | libm.so.* | libpthread.so.* | libdl.so.* | librt.so.* | ld-linux*.so.*)
      cp -L "$library" "$stage/lib/glibc/" ;;
    *) cp -L "$library" "$stage/lib/" ;;
  esac
done
strip --strip-unneeded "$stage"/lib/*.so* 2>/dev/null || true
ldd --version | head -1 | awk '{print $NF}' >"$stage/glibc_version"

if [ -f "$meshes/suzanne-sub5.ply" ]; then
  cp "$meshes/suzanne-sub5.ply" "$stage/data/"
else
  echo "pack_for_device: no $meshes/suzanne-sub5.ply; the ray benchmarks will be skipped" >&2
fi

# The Cornell box's reference, rendered here once (4,096 spp, the scene's seed + 1, as
# converge renders it), so the device's minutes go to the GPU. Kept between packs.
reference="$pack/cornell-reference-4096.exr"
mkdir -p "$pack"
if [ ! -f "$reference" ]; then
  echo "pack_for_device: rendering the Cornell reference (4,096 spp; minutes on 2 cores)"
  "$build/bench/accel/tessera-bench" converge "$root/examples/scenes/cornell.yaml" \
    --reference-spp 4096 --spp 1 --save-reference "$reference" >/dev/null
fi
cp "$reference" "$stage/data/"

# The tests name files by the path of the checkout they were built from.
grep '^CMAKE_HOME_DIRECTORY:INTERNAL=' "$build/CMakeCache.txt" | cut -d= -f2 >"$stage/source_dir"
git -C "$root" rev-parse --short HEAD >"$stage/commit"

tar -C "$stage" -cJf "$pack/pack.tar.xz" .
du -h "$pack/pack.tar.xz"
