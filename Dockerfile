# CulinaryCut server and clients on Debian 12 (bookworm).
FROM debian:bookworm
WORKDIR /opt/culinarycut
# install_deps.sh needs the pins and the Python package (it installs it into .venv), so the sources come first.
COPY . .
RUN bash scripts/install_deps.sh && rm -rf /var/lib/apt/lists/*
RUN bash scripts/build.sh
# The project virtualenv: `culinarycut` (the CLI) and its Python.
ENV PATH=/opt/culinarycut/.venv/bin:$PATH
EXPOSE 50051 5556
# Inside the container the server must listen on all of the container's interfaces; it has no TLS or
# tokens yet, so docker-compose.yml publishes the ports on the host's loopback only.
CMD ["build/server/culinarycut-server", "--listen", "0.0.0.0:50051", "--telemetry", "tcp://0.0.0.0:5556", "--insecure"]
