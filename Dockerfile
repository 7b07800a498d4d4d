# CulinaryCut server and clients on Debian 12 (bookworm).
FROM debian:bookworm
WORKDIR /opt/culinarycut
COPY scripts/install_deps.sh scripts/install_deps.sh
RUN bash scripts/install_deps.sh && rm -rf /var/lib/apt/lists/*
COPY . .
RUN bash scripts/build.sh
ENV PYTHONPATH=/opt/culinarycut/client/python
EXPOSE 50051 5556
CMD ["build/server/culinarycut-server", "--listen", "0.0.0.0:50051", "--telemetry", "tcp://0.0.0.0:5556"]
