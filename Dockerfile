# Tessera's container image: a builder stage compiles tesserad and the tessera CLI in Release;
# a slim runtime stage holds the two binaries, the shared libraries they link and nothing else.
#
#   docker build -t tessera .
#   docker run -p 127.0.0.1:50051:50051 -v tessera-data:/var/lib/tessera tessera
#   docker run -e TESSERAD_LISTEN=0.0.0.0:6000 -p 127.0.0.1:6000:6000 ... tessera   (another port)
#
# The image serves plaintext without tokens: publish the port on loopback only, or give
# tesserad a certificate, key and tokens file (README "Security") to serve a network.
#
# deploy/check-image.sh builds and checks this image without a Docker engine (buildah + podman).

# deploy/check-image.sh points these at Debian images it makes with debootstrap.
ARG BASE_IMAGE=debian:bookworm
ARG RUNTIME_IMAGE=debian:bookworm-slim

# The Debian packages holding the shared libraries tesserad, tessera and the image codecs
# module (core/image_codecs, loaded by both at their first image) link directly; apt
# brings in what those need in turn. The builder stage checks this list against the binaries
# it built (deploy/runtime-packages.sh) and the runtime stage runs ldd, so it cannot drift.
ARG RUNTIME_PACKAGES="libgrpc++1.51 libgrpc29 libprotobuf32 libabsl20220623 libopenimageio2.4 libyaml-cpp0.7 libspdlog1.10 libfmt9 libassimp5 libtbb12 libsqlite3-0 libcpp-httplib0.11 libssl3"

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
 && cmake --build /build --parallel "${JOBS:-$(nproc)}" --target tesserad tessera tessera_image_codecs

RUN install -D --strip -m 0755 /build/server/tesserad /out/usr/local/bin/tesserad \
 && install -D --strip -m 0755 /build/client/tessera /out/usr/local/bin/tessera \
 && install -D --strip -m 0644 /build/core/libtessera_image_codecs.so \
      /out/usr/local/lib/tessera/libtessera_image_codecs.so \
 && bash deploy/runtime-packages.sh --check "${RUNTIME_PACKAGES}" \
      /out/usr/local/bin/tesserad /out/usr/local/bin/tessera \
      /out/usr/local/lib/tessera/libtessera_image_codecs.so

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
RUN if ldd /usr/local/bin/tesserad /usr/local/bin/tessera \
      /usr/local/lib/tessera/libtessera_image_codecs.so | grep "not found"; then \
      echo "runtime image lacks the shared libraries above" >&2; exit 1; \
    fi

USER tessera
WORKDIR /var/lib/tessera
# The gRPC port. tesserad reads its settings from TESSERAD_* variables (README:
# "Configuration"), so the listen address is set once, here, and the HEALTHCHECK reads the
# port back from the same variable at run time: `docker run -e TESSERAD_LISTEN=0.0.0.0:6000`
# moves both. (A --listen flag would override the variable for tesserad but not for the
# check: set the variable instead.)
ARG PORT=50051
# Inside the container 0.0.0.0 is what a published port reaches, and tesserad refuses
# plaintext there unless allowed explicitly; whether the network sees it is up to how the
# port is published. To serve other machines, mount the files and set instead
#   TESSERAD_ALLOW_INSECURE_REMOTE=false TESSERAD_TLS_CERT=/etc/tessera/server.crt
#   TESSERAD_TLS_KEY=/etc/tessera/server.key TESSERAD_TOKENS=/etc/tessera/tokens.yaml
#   TESSERA_CA=/etc/tessera/ca.crt   (so the HEALTHCHECK's client trusts the certificate)
ENV TESSERAD_LISTEN=0.0.0.0:${PORT} \
    TESSERAD_DATA=/var/lib/tessera \
    TESSERAD_ALLOW_INSECURE_REMOTE=true
EXPOSE ${PORT}
VOLUME ["/var/lib/tessera"]
# `tessera health` asks the gRPC health service, which answers SERVING only once tesserad
# has opened its store and started its workers (and NOT_SERVING while it shuts down), not
# merely when the port accepts connections. ${TESSERAD_LISTEN##*:} is its port; any
# failure is exit status 1, the one Docker reads as unhealthy.
HEALTHCHECK --interval=30s --timeout=5s --start-period=10s --retries=3 \
  CMD ["sh", "-c", "tessera health --address \"127.0.0.1:${TESSERAD_LISTEN##*:}\" || exit 1"]
ENTRYPOINT ["tesserad"]
