#!/usr/bin/env bash
# Installs the C++ client from a build tree into a fresh prefix, builds a separate CMake project
# against it with find_package(culinarycut), and runs that program against a real server.
# Usage: install_and_consume.sh BUILD_DIR SOURCE_DIR SERVER_BINARY
set -euo pipefail
build_dir=$1 source_dir=$2 server=$3
work=$(mktemp -d)
server_pid=""
cleanup() { [ -n "$server_pid" ] && kill "$server_pid" 2>/dev/null; wait 2>/dev/null; rm -rf "$work"; }
trap cleanup EXIT
cmake --install "$build_dir" --component client --prefix "$work/prefix" > "$work/install.log"
test -f "$work/prefix/lib/cmake/culinarycut/culinarycutConfig.cmake"
test -f "$work/prefix/include/culinarycut/client.h"
test -f "$work/prefix/include/culinarycut/v1/simulator.grpc.pb.h"
cmake -S "$source_dir/tests/client/consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_BUILD_TYPE=Release > "$work/configure.log"
cmake --build "$work/consumer" -j "${CULINARYCUT_JOBS:-2}" > "$work/build.log"
"$server" --listen 127.0.0.1:0 --telemetry "" > "$work/server.log" 2>&1 &
server_pid=$!
for _ in $(seq 100); do
  address=$(sed -n 's/^culinarycut-server listening on //p' "$work/server.log")
  [ -n "$address" ] && break
  sleep 0.1
done
[ -n "${address:-}" ] || { echo "the server did not start:"; cat "$work/server.log"; exit 1; }
"$work/consumer/consumer" "$address"
