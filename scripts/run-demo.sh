#!/usr/bin/env bash
# `make run`: starts tesserad on a free loopback port, renders examples/scenes/cornell.yaml
# through it with the `tessera` CLI (out/cornell.exr and out/cornell.png), stops the daemon
# and exits with the render's status. The daemon's log goes to out/tesserad.log.
#
# Usage: scripts/run-demo.sh BUILD_DIR
set -euo pipefail

build_dir="${1:-build}"
# Relative to the caller's directory, before moving to the repository root.
if [ -d "$build_dir" ]; then build_dir="$(cd "$build_dir" && pwd)"; fi
cd "$(dirname "$0")/.."
daemon="$build_dir/server/tesserad"
cli="$build_dir/client/tessera"
for binary in "$daemon" "$cli"; do
  if [ ! -x "$binary" ]; then
    echo "run-demo: $binary not found; build first (make build BUILD_DIR=$build_dir)" >&2
    exit 2
  fi
done
mkdir -p out var
log=out/tesserad.log

# A port the kernel reports free right now. Another process may take it before tesserad
# binds it, so startup below is retried with a fresh port.
free_port() {
  if command -v python3 >/dev/null 2>&1; then
    python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1]); s.close()'
  else
    echo $((20000 + RANDOM % 20000))
  fi
}

daemon_pid=""
stop_daemon() {
  if [ -n "$daemon_pid" ] && kill -0 "$daemon_pid" 2>/dev/null; then
    kill -TERM "$daemon_pid" 2>/dev/null || true
    wait "$daemon_pid" 2>/dev/null || true
  fi
  daemon_pid=""
}
show_log() {
  echo "run-demo: tesserad's log ($log):" >&2
  sed 's/^/  /' "$log" >&2 || true
}
trap stop_daemon EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# Starts the daemon and waits until it answers `tessera list`; 0 when it does.
start_daemon() {
  address="127.0.0.1:$(free_port)"
  "$daemon" --listen "$address" --data var/ >"$log" 2>&1 &
  daemon_pid=$!
  local deadline=$((SECONDS + 30))
  until "$cli" list --server "$address" >/dev/null 2>&1; do
    if ! kill -0 "$daemon_pid" 2>/dev/null; then
      wait "$daemon_pid" 2>/dev/null || true
      daemon_pid=""
      return 1
    fi
    if [ "$SECONDS" -ge "$deadline" ]; then
      echo "run-demo: tesserad did not accept connections on $address within 30 s" >&2
      show_log
      exit 1
    fi
    sleep 0.2
  done
}

started=false
for attempt in 1 2 3; do
  if start_daemon; then
    started=true
    break
  fi
  echo "run-demo: tesserad exited during startup (attempt $attempt)" >&2
done
if [ "$started" != true ]; then
  show_log
  exit 1
fi
echo "run-demo: tesserad (pid $daemon_pid) is serving on $address"

begin=$EPOCHREALTIME
status=0
"$cli" render examples/scenes/cornell.yaml -o out/cornell.exr --png out/cornell.png --server "$address" ||
  status=$?
end=$EPOCHREALTIME
LC_ALL=C awk -v b="$begin" -v e="$end" 'BEGIN { printf "run-demo: render wall time %.2f s\n", e - b }'

stop_daemon
if [ "$status" -ne 0 ]; then
  echo "run-demo: the render failed (exit status $status)" >&2
  show_log
fi
exit "$status"
