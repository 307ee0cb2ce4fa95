# Tessera's container image: a builder stage compiles tesserad and the tessera CLI in Release;
# a slim runtime stage holds the two binaries, the shared libraries they link and nothing else.
#
#   docker build -t tessera .
#   docker run -p 127.0.0.1:50051:50051 -v tessera-data:/var/lib/tessera tessera
#
# The default CMD serves plaintext without tokens: publish the port on loopback only, or
# give tesserad a certificate, key and tokens file (README "Security") to serve a network.
#
# deploy/check-image.sh builds and checks this image without a Docker engine (buildah + podman).

# deploy/check-image.sh points these at Debian images it makes with debootstrap.
ARG BASE_IMAGE=debian:bookworm
ARG RUNTIME_IMAGE=debian:bookworm-slim

# The Debian packages holding the shared libraries tesserad and tessera link directly; apt
# brings in what those need in turn. The builder stage checks this list against the binaries
# it built (deploy/runtime-packages.sh) and the runtime stage runs ldd, so it cannot drift.
ARG RUNTIME_PACKAGES="libgrpc++1.51 libgrpc29 libprotobuf32 libabsl20220623 libopenimageio2.4 libyaml-cpp0.7 libspdlog1.10 libfmt9 libassimp5 libtbb12 libsqlite3-0 libssl3"

# ---------------------------------------------------------------------------------------------
FROM ${BASE_IMAGE} AS build
ARG RUNTIME_PACKAGES
# Parallel compile jobs; empty means one per CPU.
ARG JOBS=

# The same package list a developer machine uses, so the two cannot disagree.
COPY scripts/install-deps.sh /tmp/install-deps.sh
RUN bash /tmp/install-deps.sh && rm -rf /var/lib/apt/lists/* /tmp/install-deps.sh

WORKDIR /src
COPY . .
# Portable code only: no -march=native, so the image runs on any x86-64 machine.
RUN cmake -S . -B /build \
      -DCMAKE_BUILD_TYPE=Release \
      -DTESSERA_BUILD_TESTS=OFF \
      -DTESSERA_BUILD_BENCH=OFF \
      -DTESSERA_CUDA=OFF \
 && cmake --build /build --parallel "${JOBS:-$(nproc)}" --target tesserad tessera

RUN install -D --strip -m 0755 /build/server/tesserad /out/usr/local/bin/tesserad \
 && install -D --strip -m 0755 /build/client/tessera /out/usr/local/bin/tessera \
 && bash deploy/runtime-packages.sh --check "${RUNTIME_PACKAGES}" \
      /out/usr/local/bin/tesserad /out/usr/local/bin/tessera

# ---------------------------------------------------------------------------------------------
FROM ${RUNTIME_IMAGE} AS runtime
ARG RUNTIME_PACKAGES

RUN apt-get update \
 && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends ${RUNTIME_PACKAGES} \
 && rm -rf /var/lib/apt/lists/*

# tesserad never needs root: it listens on an unprivileged port and writes only its data dir.
# A fixed uid above the host's usual range, so volume ownership is predictable.
RUN groupadd --gid 10001 tessera \
 && useradd --uid 10001 --gid tessera --home-dir /var/lib/tessera --no-create-home \
      --no-log-init --shell /usr/sbin/nologin tessera \
 && install -d -o tessera -g tessera -m 0750 /var/lib/tessera

COPY --from=build /out/ /

# Fail the build, not the first start, when a shared library is missing.
RUN if ldd /usr/local/bin/tesserad /usr/local/bin/tessera | grep "not found"; then \
      echo "runtime image lacks the shared libraries above" >&2; exit 1; \
    fi

USER tessera
WORKDIR /var/lib/tessera
EXPOSE 50051
VOLUME ["/var/lib/tessera"]
# bash (always in Debian) opens a TCP connection to the gRPC port: no curl or probe binary
# needed. It checks the default port only; change it too when overriding --listen.
HEALTHCHECK --interval=30s --timeout=5s --start-period=10s --retries=3 \
  CMD ["bash", "-c", "exec 3<>/dev/tcp/127.0.0.1/50051"]
ENTRYPOINT ["tesserad"]
# Inside the container 0.0.0.0 is what a published port reaches, and plaintext there is
# refused unless allowed explicitly; whether the network sees it is up to how the port is
# published. To serve other machines, mount the files and run with
#   --listen 0.0.0.0:50051 --data /var/lib/tessera --tls-cert /etc/tessera/server.crt
#   --tls-key /etc/tessera/server.key --tokens /etc/tessera/tokens.yaml
CMD ["--listen", "0.0.0.0:50051", "--data", "/var/lib/tessera", "--allow-insecure-remote"]
