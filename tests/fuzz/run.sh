#!/usr/bin/env bash
# Runs each libFuzzer target of BUILD_DIR for SECONDS on a working copy of its seed corpus:
#   tests/fuzz/run.sh build-fuzz 600
# New inputs go to BUILD_DIR/corpus-NAME, crashes to BUILD_DIR/findings-NAME. Exits non-zero
# when a target found something.
set -euo pipefail
build=${1:?usage: run.sh BUILD_DIR SECONDS}
seconds=${2:-60}
root=$(cd "$(dirname "$0")/../.." && pwd)
status=0
for name in yaml proto; do
  target="$build/tests/fuzz/fuzz_${name}_scene"
  corpus="$build/corpus-$name"
  findings="$build/findings-$name"
  mkdir -p "$corpus" "$findings"
  if [ "$name" = yaml ]; then
    cp -n "$root"/examples/scenes/*.yaml "$root"/tests/fuzz/corpus/yaml/*.yaml "$corpus"/
  else
    cp -n "$build"/tests/fuzz/proto-seeds/*.pb "$corpus"/
    find "$root/tests/fuzz/corpus/proto" -type f ! -name .keep -exec cp -n {} "$corpus"/ \;
  fi
  echo "== fuzz_${name}_scene for ${seconds} s"
  # rss_limit: a scene may legally take memory, but the targets' limits keep it small.
  if ! ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    "$target" -max_total_time="$seconds" -rss_limit_mb=4096 -timeout=20 -max_len=65536 \
    -artifact_prefix="$findings/" -print_final_stats=1 "$corpus"; then
    status=1
  fi
done
exit $status
