# CulinaryCut on Debian 12 (bookworm), in three stages:
#   build   compilers, -dev packages and the sources; builds the server and the Python client
#   server  the server binary, its assets and only the shared libraries it loads (no compilers); non-root
#   client  the Python packages (culinarycut with every extra its commands import: data's h5py, safety
#           fit's scipy; the policy adapters; the learned policy with Debian's CPU torch) and their
#           virtualenv; non-root
FROM debian:bookworm AS build
# The commit the image is built from, which GetServerInfo reports as the build id (the benchmark runner
# refuses to mix builds, and every image reporting "unknown" would defeat that). .git stays out of the
# build context, so the build is told: --build-arg CULINARYCUT_BUILD_ID=$(git rev-parse --short=12 HEAD)
# (cmake/CulinaryCutBuildId.cmake reads the variable).
ARG CULINARYCUT_BUILD_ID
RUN test -n "$CULINARYCUT_BUILD_ID" || { echo "the build id is missing: docker build --build-arg" \
      "CULINARYCUT_BUILD_ID=\$(git rev-parse --short=12 HEAD) ... (docker compose: set CULINARYCUT_BUILD_ID)" >&2; \
      exit 1; }
WORKDIR /opt/culinarycut
# install_deps.sh needs the pins and the Python package (it installs it into .venv), so the sources come first.
COPY . .
RUN bash scripts/install_deps.sh && bash scripts/build.sh
SHELL ["/bin/bash", "-o", "pipefail", "-c"]
# The Debian packages that own the libraries the server links, for the runtime stage to install
# (bookworm registers some libraries under /lib and some under /usr/lib: try the path as ldd prints
# it, then resolved). A library no package owns stops the build.
# Our own MPM library (build/lib, one build per x86-64 level) is copied, not installed.
RUN ! ldd build/server/culinarycut-server | grep "not found" \
    && for lib in $(ldd build/server/culinarycut-server | awk '/=> \// && $3 !~ /^\/opt\/culinarycut\// {print $3}'); do \
      dpkg -S "$lib" 2>/dev/null || dpkg -S "$(realpath "$lib")" 2>/dev/null \
        || { echo "no Debian package owns $lib" >&2; exit 1; }; \
    done | cut -d: -f1 | sort -u > /opt/culinarycut/runtime-packages.txt

FROM debian:bookworm-slim AS server
COPY --from=build /opt/culinarycut/runtime-packages.txt /tmp/runtime-packages.txt
# Mesa's EGL and software rasteriser are loaded at run time (dlopen), so ldd cannot see them.
RUN apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
      $(cat /tmp/runtime-packages.txt) libegl-mesa0 libgl1-mesa-dri \
    && rm -rf /var/lib/apt/lists/* /tmp/runtime-packages.txt \
    && useradd --system --no-create-home --shell /usr/sbin/nologin culinarycut
COPY --from=build /opt/culinarycut/build/server/culinarycut-server /opt/culinarycut/bin/culinarycut-server
# The MPM library, once per x86-64 level: the loader picks the best the CPU runs (lib/glibc-hwcaps/).
COPY --from=build /opt/culinarycut/build/lib /opt/culinarycut/lib
# The binary finds its libraries where the image put them (ldd checked the build stage's only).
RUN /opt/culinarycut/bin/culinarycut-server --version
COPY --from=build /opt/culinarycut/assets /opt/culinarycut/assets
COPY --from=build /opt/culinarycut/scripts/container_entrypoint.sh /opt/culinarycut/bin/container-entrypoint
USER culinarycut
WORKDIR /opt/culinarycut
EXPOSE 50051
# TLS with bearer tokens by default, on the container's interfaces so that a published port reaches it:
# mount the certificate, its key and the token file at /run/secrets/ (scripts/make_server_secrets.sh makes
# them; docker-compose.yml mounts them). Without them the entrypoint refuses to start and says what to mount.
# Telemetry (unencrypted) is off. Flags given to `docker run IMAGE ...` replace these (docs/deployment.md).
ENTRYPOINT ["/bin/sh", "/opt/culinarycut/bin/container-entrypoint", "/opt/culinarycut/bin/culinarycut-server"]
CMD ["--listen", "0.0.0.0:50051", "--tls-cert", "/run/secrets/server.pem", "--tls-key", "/run/secrets/server.key", \
     "--token-file", "/run/secrets/tokens.txt"]

FROM debian:bookworm-slim AS client
RUN apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
      python3 python3-grpcio python3-protobuf python3-numpy python3-zmq python3-opencv python3-jsonschema \
      python3-matplotlib python3-pil python3-h5py python3-scipy python3-torch python3-torchvision \
    && rm -rf /var/lib/apt/lists/* \
    && useradd --create-home --shell /bin/bash culinarycut
COPY --from=build /opt/culinarycut/.venv /opt/culinarycut/.venv
COPY --from=build /opt/culinarycut/client/python /opt/culinarycut/client/python
COPY --from=build /opt/culinarycut/policies /opt/culinarycut/policies
COPY --from=build /opt/culinarycut/learning /opt/culinarycut/learning
COPY --from=build /opt/culinarycut/assets/language /opt/culinarycut/assets/language
COPY --from=build /opt/culinarycut/benchmarks /opt/culinarycut/benchmarks
ENV PATH=/opt/culinarycut/.venv/bin:$PATH CULINARYCUT_BENCHMARKS=/opt/culinarycut/benchmarks
USER culinarycut
WORKDIR /home/culinarycut
CMD ["culinarycut", "--help"]
