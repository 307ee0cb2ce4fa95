#!/usr/bin/env bash
# Builds Tessera's container image from the Dockerfile WITHOUT a Docker engine and checks
# that tesserad runs inside it. Slow (a full Release build inside the builder stage), so it
# is not part of `make test`. Run as root on Debian bookworm:
#
#   sudo deploy/check-image.sh              build the committed tree (git HEAD) and check it
#   sudo deploy/check-image.sh --worktree   build the working tree as it is, edits included
#   sudo deploy/check-image.sh --base-only  only prepare the cached Debian base images
#   sudo deploy/check-image.sh --check-only check an image built before (TESSERA_IMAGE_TAG)
#
# How: debootstrap makes a Debian bookworm rootfs from the mirror this machine's apt already
# uses (no registry needed), podman imports it as localhost/debian:bookworm and, slimmed like
# the official image, as localhost/debian:bookworm-slim; buildah builds the Dockerfile on top
# of those with chroot isolation and the vfs storage driver (no daemon, no overlay mounts);
# podman then runs `tesserad --version` in the result, probes the HEALTHCHECK and renders
# examples/scenes/cornell.yaml through the container's tesserad with its tessera CLI (both
# load the image codecs module from /usr/local/lib/tessera: for the EXR tiles and the file).
#
# Everything lives under TESSERA_IMAGE_CACHE, including a container store of its own, so the
# machine's default podman storage is left alone and a second run reuses the base images.
#
# Environment:
#   TESSERA_IMAGE_CACHE    cache and container store (default /var/tmp/tessera-image-cache)
#   TESSERA_IMAGE_TAG      tag of the built image (default localhost/tessera:check)
#   TESSERA_DEBIAN_MIRROR  Debian mirror (default: the one apt uses here for bookworm)
#   JOBS                   parallel compile jobs in the builder stage (default 2)
#   TESSERA_LAYERS         1 to cache build layers between runs (vfs copies every layer, so
#                          this trades disk and commit time for faster rebuilds; default 0)
set -euo pipefail

readonly SUITE=bookworm
REPO_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
readonly REPO_ROOT
readonly CACHE_DIR="${TESSERA_IMAGE_CACHE:-/var/tmp/tessera-image-cache}"
readonly IMAGE_TAG="${TESSERA_IMAGE_TAG:-localhost/tessera:check}"
readonly BASE_IMAGE="localhost/debian:${SUITE}"
readonly RUNTIME_IMAGE="localhost/debian:${SUITE}-slim"
readonly JOBS="${JOBS:-2}"
# A store of our own, always vfs: overlay needs kernel support that sandboxes often lack.
readonly STORE=(--root "${CACHE_DIR}/storage" --runroot "${CACHE_DIR}/run" --storage-driver vfs)
# No systemd or journald is assumed to be running. runc, not crun (podman's default): crun
# refuses hosts whose cgroups are in hybrid v1/v2 mode, as some VMs and CI runners are.
readonly PODMAN=(podman "${STORE[@]}" --runtime runc --cgroup-manager cgroupfs --events-backend file)
readonly BUILDAH=(buildah "${STORE[@]}")

started_at=${SECONDS}
step() { printf '\n== [%4ds] %s\n' "$((SECONDS - started_at))" "$*"; }
die() {
  echo "check-image: FAILED: $*" >&2
  exit 1
}

base_only=0
check_only=0
use_worktree=0
for argument in "$@"; do
  case "$argument" in
    --base-only) base_only=1 ;;
    --worktree) use_worktree=1 ;;
    --check-only) check_only=1 ;;
    -h | --help)
      sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'
      exit 0
      ;;
    *) die "unknown argument '$argument' (expected --base-only, --check-only, --worktree or --help)" ;;
  esac
done

[ "$(id -u)" -eq 0 ] || die "must run as root (debootstrap, podman import and buildah need it)"

# ---------------------------------------------------------------------------------------------
# Tools: buildah, podman and debootstrap from Debian's own archive.
ensure_tools() {
  local wanted=(buildah podman runc debootstrap) missing=() p
  for p in "${wanted[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    step "installing ${missing[*]} from apt"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends "${missing[@]}"
  fi
  echo "buildah: $(buildah --version)"
  echo "podman:  $(podman --version)"
}

# ---------------------------------------------------------------------------------------------
# The mirror apt uses here for a suite: deb822 *.sources first, then one-line *.list files.
apt_uri_for_suite() {
  local suite=$1 f uri
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] || continue
    uri=$(awk -v suite="$suite" '
      BEGIN { RS = ""; FS = "\n" }
      {
        types = ""; uris = ""; suites = ""; enabled = "yes"
        for (i = 1; i <= NF; i++) {
          line = $i
          if (line ~ /^[ \t]*#/) continue
          split(line, kv, ":")
          key = tolower(kv[1]); value = substr(line, length(kv[1]) + 2)
          gsub(/^[ \t]+|[ \t]+$/, "", value)
          if (key == "types") types = value
          else if (key == "uris") uris = value
          else if (key == "suites") suites = value
          else if (key == "enabled") enabled = tolower(value)
        }
        if (enabled == "no" || (" " types " ") !~ / deb /) next
        if ((" " suites " ") ~ (" " suite " ")) { split(uris, u, " "); print u[1]; exit }
      }' "$f")
    if [ -n "$uri" ]; then
      echo "${uri%/}"
      return 0
    fi
  done
  for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
    [ -f "$f" ] || continue
    uri=$(sed -E 's/\[[^]]*\]//' "$f" | awk -v suite="$suite" '$1 == "deb" && $3 == suite { print $2; exit }')
    if [ -n "$uri" ]; then
      echo "${uri%/}"
      return 0
    fi
  done
  return 1
}

# ---------------------------------------------------------------------------------------------
# Base images. The rootfs is configured the way the official debian images are (debuerreotype):
# deb822 sources for the suite, its updates and security; apt that keeps no caches; and, for
# the -slim variant, dpkg path excludes that drop documentation, man pages and locales.
configure_rootfs() {
  local rootfs=$1 mirror=$2 security=$3
  rm -f "${rootfs}/etc/apt/sources.list"
  cat >"${rootfs}/etc/apt/sources.list.d/debian.sources" <<EOF
Types: deb
URIs: ${mirror}
Suites: ${SUITE} ${SUITE}-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb
URIs: ${security}
Suites: ${SUITE}-security
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
  cat >"${rootfs}/etc/apt/apt.conf.d/docker-clean" <<'EOF'
DPkg::Post-Invoke { "rm -f /var/cache/apt/archives/*.deb /var/cache/apt/archives/partial/*.deb /var/cache/apt/*.bin || true"; };
APT::Update::Post-Invoke { "rm -f /var/cache/apt/archives/*.deb /var/cache/apt/archives/partial/*.deb /var/cache/apt/*.bin || true"; };
Dir::Cache::pkgcache "";
Dir::Cache::srcpkgcache "";
EOF
  echo 'Acquire::Languages "none";' >"${rootfs}/etc/apt/apt.conf.d/docker-no-languages"
  printf 'Acquire::GzipIndexes "true";\nAcquire::CompressionTypes::Order:: "gz";\n' \
    >"${rootfs}/etc/apt/apt.conf.d/docker-gzip-indexes"
  printf 'Apt::AutoRemove::SuggestsImportant "false";\n' \
    >"${rootfs}/etc/apt/apt.conf.d/docker-autoremove-suggests"
  rm -rf "${rootfs}"/var/lib/apt/lists/* "${rootfs}"/var/cache/apt/*.bin \
    "${rootfs}"/var/cache/apt/archives/*.deb "${rootfs}"/var/log/*.log \
    "${rootfs}"/var/cache/debconf/*-old "${rootfs}"/var/lib/dpkg/*-old
  # The container engine provides these at run time.
  : >"${rootfs}/etc/resolv.conf"
  : >"${rootfs}/etc/hostname"
  : >"${rootfs}/etc/machine-id"
}

slim_rootfs() {
  local rootfs=$1
  cat >"${rootfs}/etc/dpkg/dpkg.cfg.d/docker" <<'EOF'
# Drop documentation, man pages and translations, keeping copyright notices (as debian:*-slim).
path-exclude /usr/share/doc/*
path-include /usr/share/doc/*/copyright
path-exclude /usr/share/groff/*
path-exclude /usr/share/info/*
path-exclude /usr/share/linda/*
path-exclude /usr/share/lintian/overrides/*
path-exclude /usr/share/locale/*
path-exclude /usr/share/man/*
EOF
  find "${rootfs}/usr/share/doc" -mindepth 1 ! -type d ! -name copyright -delete
  find "${rootfs}/usr/share/doc" -mindepth 1 -type d -empty -delete
  rm -rf "${rootfs}"/usr/share/{groff,info,linda,locale,man}/* "${rootfs}"/usr/share/lintian/overrides/*
}

# Removes a scratch rootfs without ever following a mount (debootstrap mounts /proc and /sys
# inside the target and may leave them behind when it fails).
remove_rootfs() {
  local dir=$1 mnt
  [ -d "$dir" ] || return 0
  for mnt in $(findmnt -rn -o TARGET | grep -F "${dir}/" | sort -r || true); do
    umount -l "$mnt" || true
  done
  rm -rf --one-file-system "$dir"
}

make_base_tarballs() {
  local full_tar="${CACHE_DIR}/debian-${SUITE}-minbase.tar"
  local slim_tar="${CACHE_DIR}/debian-${SUITE}-slim.tar"
  local rootfs="${CACHE_DIR}/rootfs.tmp"
  if [ -s "$full_tar" ] && [ -s "$slim_tar" ]; then
    echo "reusing cached base rootfs: ${full_tar}, ${slim_tar}"
    return 0
  fi
  local mirror security
  mirror="${TESSERA_DEBIAN_MIRROR:-$(apt_uri_for_suite "$SUITE" || echo http://deb.debian.org/debian)}"
  security="$(apt_uri_for_suite "${SUITE}-security" || echo "${mirror%/debian}/debian-security")"
  step "debootstrap --variant=minbase ${SUITE} from ${mirror} (security: ${security})"
  remove_rootfs "$rootfs"
  trap 'remove_rootfs "'"$rootfs"'"' EXIT
  debootstrap --variant=minbase "$SUITE" "$rootfs" "$mirror" >"${CACHE_DIR}/debootstrap.log" 2>&1 ||
    {
      tail -n 30 "${CACHE_DIR}/debootstrap.log" >&2
      die "debootstrap failed; full log in ${CACHE_DIR}/debootstrap.log"
    }
  configure_rootfs "$rootfs" "$mirror" "$security"
  tar --numeric-owner -C "$rootfs" -cf "${full_tar}.tmp" .
  slim_rootfs "$rootfs"
  tar --numeric-owner -C "$rootfs" -cf "${slim_tar}.tmp" .
  mv "${full_tar}.tmp" "$full_tar"
  mv "${slim_tar}.tmp" "$slim_tar"
  remove_rootfs "$rootfs"
  trap - EXIT
  base_is_new=1
}

import_base_images() {
  local -A tarball=(
    ["$BASE_IMAGE"]="${CACHE_DIR}/debian-${SUITE}-minbase.tar"
    ["$RUNTIME_IMAGE"]="${CACHE_DIR}/debian-${SUITE}-slim.tar"
  )
  local image
  for image in "$BASE_IMAGE" "$RUNTIME_IMAGE"; do
    if [ "$base_is_new" -eq 1 ] || ! "${PODMAN[@]}" image exists "$image"; then
      step "podman import ${tarball[$image]} as ${image}"
      "${PODMAN[@]}" import --quiet - "$image" <"${tarball[$image]}" >/dev/null
    fi
    printf '%-40s %s\n' "$image" "$("${PODMAN[@]}" image inspect --format '{{.Size}}' "$image" |
      numfmt --to=iec-i --suffix=B)"
  done
}

# ---------------------------------------------------------------------------------------------
# The build context: by default an export of the committed tree, so edits in progress in the
# working tree (other people's included) neither break nor leak into the checked image.
prepare_context() {
  if [ "$use_worktree" -eq 1 ] || ! command -v git >/dev/null ||
    ! git -C "$REPO_ROOT" rev-parse --verify -q HEAD >/dev/null; then
    CONTEXT_DIR=$REPO_ROOT
    step "build context: working tree ${CONTEXT_DIR}"
    return 0
  fi
  CONTEXT_DIR="${CACHE_DIR}/context"
  step "build context: commit $(git -C "$REPO_ROOT" log -1 --format='%h %s') -> ${CONTEXT_DIR}"
  rm -rf --one-file-system "$CONTEXT_DIR"
  mkdir -p "$CONTEXT_DIR"
  git -C "$REPO_ROOT" archive --format=tar HEAD | tar -x -C "$CONTEXT_DIR"
}

# Podman asks for nofile=1048576 and a large nproc by default; where the hard limits are lower
# (sandboxes, CI) the runtime cannot set them and the container does not start. Ask for what
# is grantable: the shell's hard limits, nproc at most 32768, which podman could grant on
# every machine tried.
limit_at_most() {
  local value
  value=$(ulimit -H "$1")
  if [ "$value" = unlimited ] || [ "$value" -gt "$2" ]; then value=$2; fi
  echo "$value"
}
nofile=$(limit_at_most -n 1048576)
nproc=$(limit_at_most -u 32768)
readonly RUN_FLAGS=(--network none --ulimit "nofile=${nofile}:${nofile}" --ulimit "nproc=${nproc}:${nproc}")

build_image() {
  local layers=false
  [ "${TESSERA_LAYERS:-0}" = 1 ] && layers=true
  step "buildah bud (vfs, chroot isolation, JOBS=${JOBS}, layers=${layers}) -> ${IMAGE_TAG}"
  # --format docker: the OCI image format has no HEALTHCHECK field and would drop it.
  # --pull=never: the base images come from the local store, never from a registry.
  nice -n 10 "${BUILDAH[@]}" bud \
    --isolation chroot \
    --format docker \
    --pull=never \
    --layers="${layers}" \
    --build-arg BASE_IMAGE="$BASE_IMAGE" \
    --build-arg RUNTIME_IMAGE="$RUNTIME_IMAGE" \
    --build-arg JOBS="$JOBS" \
    --file "${CONTEXT_DIR}/Dockerfile" \
    --tag "$IMAGE_TAG" \
    "$CONTEXT_DIR"
}

check_image() {
  step "podman run --rm ${IMAGE_TAG} --version"
  local version
  version=$("${PODMAN[@]}" run --rm "${RUN_FLAGS[@]}" --no-healthcheck "$IMAGE_TAG" --version) ||
    die "tesserad --version failed inside the image"
  echo "$version"
  [ -n "$version" ] || die "tesserad --version printed nothing"

  step "podman run --rm --entrypoint tessera ${IMAGE_TAG} --help"
  "${PODMAN[@]}" run --rm "${RUN_FLAGS[@]}" --no-healthcheck --entrypoint tessera "$IMAGE_TAG" \
    --help >/dev/null ||
    die "tessera --help failed inside the image"
  echo "tessera CLI runs"

  step "image configuration"
  "${PODMAN[@]}" image inspect --format \
    'user={{.Config.User}} entrypoint={{.Config.Entrypoint}} cmd={{.Config.Cmd}} ports={{.Config.ExposedPorts}} volumes={{.Config.Volumes}}' \
    "$IMAGE_TAG"
  local healthcheck
  healthcheck=$("${PODMAN[@]}" image inspect --format '{{.HealthCheck}}' "$IMAGE_TAG")
  echo "healthcheck=${healthcheck}"
  case "$healthcheck" in "" | "<nil>") die "the image has no HEALTHCHECK" ;; esac

  step "start tesserad in a container and run its HEALTHCHECK"
  # No automatic health timer (that needs systemd): the loop below runs the check itself.
  # Podman's complaints about the missing systemd go to a log, shown only on failure.
  local name="tessera-check-$$" log="${CACHE_DIR}/healthcheck.log"
  "${PODMAN[@]}" run -d "${RUN_FLAGS[@]}" --health-interval disable --name "$name" \
    -v "${REPO_ROOT}/examples/scenes:/scenes:ro" "$IMAGE_TAG" >"$log" 2>&1 || {
    cat "$log" >&2
    die "could not start tesserad in a container"
  }
  local healthy=0 attempt
  for attempt in $(seq 1 20); do
    if "${PODMAN[@]}" healthcheck run "$name" >>"$log" 2>&1; then
      healthy=1
      break
    fi
    if [ "$("${PODMAN[@]}" inspect --format '{{.State.Running}}' "$name" 2>>"$log")" != true ]; then
      break
    fi
    sleep 1
  done
  local rendered=0
  if [ "$healthy" -eq 1 ]; then
    step "render examples/scenes/cornell.yaml through the container's tesserad"
    # A job as a user submits one: the CLI sends the scene, the daemon renders and encodes
    # EXR tiles, the CLI writes the file. Both load the image codecs module.
    if "${PODMAN[@]}" exec "$name" tessera render --width 32 --height 32 --spp 4 \
      /scenes/cornell.yaml -o /var/lib/tessera/cornell.exr >>"$log" 2>&1 &&
      "${PODMAN[@]}" exec "$name" test -s /var/lib/tessera/cornell.exr >>"$log" 2>&1; then
      rendered=1
      tail -n 1 "$log"
    fi
  fi
  "${PODMAN[@]}" logs "$name" 2>&1 | tail -n 5
  # SIGTERM, then SIGKILL after 10 s: a clean shutdown shows as a prompt removal.
  local stop_started=${SECONDS}
  "${PODMAN[@]}" rm -f -t 10 "$name" >>"$log" 2>&1
  echo "container stopped and removed in $((SECONDS - stop_started)) s"
  if [ "$healthy" -ne 1 ]; then
    tail -n 20 "$log" >&2
    die "tesserad did not become healthy (HEALTHCHECK failed)"
  fi
  echo "healthcheck passed after ${attempt} attempt(s)"
  if [ "$rendered" -ne 1 ]; then
    tail -n 20 "$log" >&2
    die "the container's tesserad did not render examples/scenes/cornell.yaml"
  fi
  echo "rendered a 32x32 Cornell box through the container's tesserad"

  step "image size"
  local bytes
  bytes=$("${PODMAN[@]}" image inspect --format '{{.Size}}' "$IMAGE_TAG")
  echo "${IMAGE_TAG}: $(numfmt --to=iec-i --suffix=B "$bytes") (${bytes} bytes)"
}

# ---------------------------------------------------------------------------------------------
mkdir -p "$CACHE_DIR"
ensure_tools
if [ "$check_only" -eq 1 ]; then
  "${PODMAN[@]}" image exists "$IMAGE_TAG" || die "no image ${IMAGE_TAG} to check; build it first"
  check_image
  step "image check passed in $((SECONDS - started_at)) s"
  exit 0
fi
base_is_new=0 # set by make_base_tarballs when it made new tarballs
make_base_tarballs
import_base_images
if [ "$base_only" -eq 1 ]; then
  step "base images ready"
  exit 0
fi
prepare_context
for required in Dockerfile server/main.cpp client/main.cpp; do
  [ -f "${CONTEXT_DIR}/${required}" ] || die "${required} is missing from the build context"
done
build_image
check_image
if [ "${TESSERA_LAYERS:-0}" != 1 ]; then
  # Earlier images of the same tag are left untagged by the new one; vfs stores each in full.
  "${PODMAN[@]}" image prune -f >/dev/null
fi
step "image check passed in $((SECONDS - started_at)) s"
