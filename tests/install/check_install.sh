#!/usr/bin/env bash
# CTest InstallTree.ConsumerFindsThePackage: `cmake --install` into a fresh prefix, then use
# what it installed as a user would:
#   - the files: tesserad, tessera, the image codecs module, the systemd unit (ExecStart at this prefix), the example
#     configuration, the CMake package, the Python package;
#   - the installed tesserad, started with the example configuration (flags override its
#     address and data folder), which must load without a warning;
#   - the installed Python package submits and renders a small Cornell box (skipped when a
#     Python module is missing);
#   - a tiny CMake project (tests/install/consumer) built against the prefix with
#     find_package(tessera CONFIG REQUIRED), linking tessera::client, lists the daemon's jobs.
#
# Usage: check_install.sh BUILD_DIR WORK_DIR CXX_COMPILER PYTHON SOURCE_DIR PYTHON_PACKAGE
# (PYTHON_PACKAGE: yes when the build has the Python package, no otherwise)
set -euo pipefail
build_dir=$1 work=$2 cxx=$3 python=$4 source_dir=$5 python_package=$6

fail() {
  echo "check_install: $*" >&2
  exit 1
}

rm -rf "$work"
mkdir -p "$work"
prefix="$work/prefix"
daemon_pid=""
cleanup() {
  if [ -n "$daemon_pid" ]; then kill -TERM "$daemon_pid" 2>/dev/null || true; wait "$daemon_pid" 2>/dev/null || true; fi
}
trap cleanup EXIT

cmake --install "$build_dir" --prefix "$prefix" >"$work/install.log" || fail "cmake --install failed: $(cat "$work/install.log")"

for file in bin/tesserad bin/tessera lib/tessera/libtessera_image_codecs.so lib/systemd/system/tesserad.service share/tessera/tesserad.yaml \
  lib/cmake/tessera/tesseraConfig.cmake lib/cmake/tessera/tesseraTargets.cmake \
  include/tessera/client/client.hpp include/tessera/tessera/v1/render.grpc.pb.h; do
  [ -e "$prefix/$file" ] || fail "not installed: $file"
done
grep -q "^ExecStart=$prefix/bin/tesserad " \
  "$prefix/lib/systemd/system/tesserad.service" || fail "the unit's ExecStart is not $prefix/bin/tesserad"
site=""
if [ "$python_package" = yes ]; then
  site=$(find "$prefix/lib" -maxdepth 3 -type d -name dist-packages | head -n 1)
  [ -f "$site/tessera_client/__init__.py" ] || fail "the Python package is not installed under $prefix/lib"
  grep -q "\"$prefix/bin/tessera\"" "$site/tessera_client/_config.py" ||
    fail "the Python package does not name $prefix/bin/tessera"
fi

# The installed daemon with the example configuration; the port it reports on stdout.
"$prefix/bin/tesserad" --config "$prefix/share/tessera/tesserad.yaml" --listen 127.0.0.1:0 \
  --data "$work/data" --threads 2 >"$work/tesserad.out" 2>"$work/tesserad.log" &
daemon_pid=$!
port=""
for _ in $(seq 1 300); do
  port=$(sed -n 's/.*(port \([0-9]*\)).*/\1/p' "$work/tesserad.out")
  [ -n "$port" ] && break
  kill -0 "$daemon_pid" 2>/dev/null || fail "tesserad exited: $(cat "$work/tesserad.log")"
  sleep 0.1
done
[ -n "$port" ] || fail "tesserad did not report its port"
# It loads the image codecs at start, and must take the prefix's module, not the build tree's.
grep -q "$(realpath "$prefix")/lib/tessera/libtessera_image_codecs.so" "/proc/$daemon_pid/maps" ||
  fail "the installed tesserad did not load $prefix/lib/tessera/libtessera_image_codecs.so: $(grep image_codecs "/proc/$daemon_pid/maps" || echo none)"
address="127.0.0.1:$port"
if grep -Eiq "warn|unknown" "$work/tesserad.log"; then
  fail "the example configuration gave warnings: $(cat "$work/tesserad.log")"
fi

expected_jobs=0
if [ -n "$site" ] && "$python" -c "import grpc, google.protobuf, numpy, OpenImageIO, yaml" 2>/dev/null; then
  PYTHONPATH="$site" PYTHONDONTWRITEBYTECODE=1 "$python" - "$address" "$source_dir" "$site" <<'PY' ||
import sys
import tessera_client
assert tessera_client.__file__.startswith(sys.argv[3]), tessera_client.__file__
with tessera_client.Client(sys.argv[1]) as client:
    image = client.render(sys.argv[2] + "/examples/scenes/cornell.yaml", width=32, height=24, spp=2)
assert image.shape == (24, 32, 4), image.shape
print("python: rendered", image.shape)
PY
    fail "the installed Python package could not render"
  expected_jobs=1
else
  echo "check_install: no Python package or modules; the Python package's render is not checked"
fi

cmake -S "$source_dir/tests/install/consumer" -B "$work/consumer" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_PREFIX_PATH="$prefix" >"$work/consumer-configure.log" 2>&1 ||
  fail "configuring the consumer failed: $(cat "$work/consumer-configure.log")"
cmake --build "$work/consumer" >"$work/consumer-build.log" 2>&1 ||
  fail "building the consumer failed: $(cat "$work/consumer-build.log")"
output=$("$work/consumer/tessera_consumer" "$address") || fail "the consumer failed: $output"
echo "$output"
[ "$(head -n 1 <<<"$output")" = "jobs: $expected_jobs" ] || fail "expected 'jobs: $expected_jobs'"
if [ "$expected_jobs" = 1 ]; then
  grep -q " JOB_STATE_COMPLETED$" <<<"$output" || fail "the Python client's job is not completed"
fi

cleanup
daemon_pid=""
rm -rf "$work"
echo "check_install: ok"
