#!/usr/bin/env bash
# Prints the Debian packages that provide the shared libraries the given ELF binaries link
# directly (their DT_NEEDED entries), one per line. apt installs what those libraries need in
# turn, so this is the whole runtime package list a slim image needs for the binaries.
#
#   deploy/runtime-packages.sh build/server/tesserad build/client/tessera
#   deploy/runtime-packages.sh --check "libfoo1 libbar2" BINARY...
#
# With --check, compares the packages found with a declared list (the Dockerfile's
# RUNTIME_PACKAGES) instead: exits non-zero when a needed package is missing from it, and
# warns about declared packages no binary needs. Needs binutils (readelf), ldd and dpkg.
set -euo pipefail

# Every Debian image has these (apt depends on them), so no list needs to name them.
readonly BASE_PACKAGES="libc6 libgcc-s1 libstdc++6"

declared=""
check=0
if [ "${1:-}" = "--check" ]; then
  [ $# -ge 3 ] || {
    echo "usage: $0 --check 'PACKAGE...' BINARY..." >&2
    exit 2
  }
  check=1
  declared=$2
  shift 2
fi
[ $# -ge 1 ] || {
  echo "usage: $0 [--check 'PACKAGE...'] BINARY..." >&2
  exit 2
}

# The package owning a file; Debian's merged /usr means dpkg may know it under /lib or /usr/lib.
package_of() {
  local path=$1 candidate
  for candidate in "$path" "$(realpath "$path")" "/usr${path}" "${path#/usr}"; do
    if owner=$(dpkg -S "$candidate" 2>/dev/null | head -n 1); then
      echo "${owner%%:*}"
      return 0
    fi
  done
  return 1
}

failed=0
packages=()
for binary in "$@"; do
  [ -f "$binary" ] || {
    echo "runtime-packages: no such file: $binary" >&2
    exit 1
  }
  # Where the dynamic loader finds each library; ldd reports the whole closure, of which only
  # the direct DT_NEEDED entries count.
  resolved=$(ldd "$binary")
  while read -r library; do
    path=$(awk -v lib="$library" '$1 == lib && $2 == "=>" { print $3 }' <<<"$resolved")
    if [ -z "$path" ]; then
      # The dynamic loader itself is listed by its absolute path, without "=>".
      path=$(awk -v lib="$library" 'index($1, "/" lib) { print $1 }' <<<"$resolved")
    fi
    if [ -z "$path" ] || [ "$path" = "not" ]; then
      echo "runtime-packages: $binary needs $library, which the loader does not find" >&2
      failed=1
      continue
    fi
    if ! package=$(package_of "$path"); then
      echo "runtime-packages: $binary needs $path, which no Debian package owns" >&2
      failed=1
      continue
    fi
    packages+=("$package")
  done < <(readelf -d "$binary" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p')
done
[ "$failed" -eq 0 ] || exit 1

needed=$(printf '%s\n' "${packages[@]}" | sort -u)
if [ "$check" -eq 0 ]; then
  echo "$needed"
  exit 0
fi

missing=()
for package in $needed; do
  case " $declared $BASE_PACKAGES " in
    *" $package "*) ;;
    *) missing+=("$package") ;;
  esac
done
for package in $declared; do
  grep -qx -- "$package" <<<"$needed" ||
    echo "runtime-packages: warning: $package is declared but no binary links it directly" >&2
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "runtime-packages: the binaries need ${missing[*]}, missing from the declared list" >&2
  exit 1
fi
echo "runtime-packages: the declared list covers every library the binaries link: $(tr "\n" " " <<<"$needed")"
