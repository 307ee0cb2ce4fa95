#!/usr/bin/env bash
# Installs the Debian packages Tessera needs, skipping those already present.
# Run as root (or with sudo available). Safe to run repeatedly.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler
  libopenimageio-dev openimageio-tools
  libyaml-cpp-dev libspdlog-dev libglm-dev libsqlite3-dev libsqlitecpp-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libassimp-dev libcli11-dev nlohmann-json3-dev libtbb-dev libcpp-httplib-dev
  libssl-dev openssl
  python3-grpcio python3-protobuf python3-numpy python3-openimageio python3-yaml
)
# Optional: Embree is only a benchmark yardstick; never a dependency of tesserad. clang and
# its runtime libraries (libFuzzer) build `make fuzz`; `make test` does without them.
optional_packages=(libembree-dev clang libclang-rt-14-dev)

missing=()
for p in "${packages[@]}" "${optional_packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} required packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
# Required packages must install; the optional ones may fail without stopping the build.
required_missing=()
for p in "${missing[@]}"; do
  [[ " ${optional_packages[*]} " == *" $p "* ]] || required_missing+=("$p")
done
if [ ${#required_missing[@]} -gt 0 ]; then
  $SUDO apt-get install -y -qq --no-install-recommends "${required_missing[@]}"
fi
for p in "${optional_packages[@]}"; do
  $SUDO apt-get install -y -qq --no-install-recommends "$p" || echo "install-deps: optional $p unavailable"
done
