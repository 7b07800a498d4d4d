#!/usr/bin/env bash
# Starts a server on a free loopback port and runs the C++ conformance runner against it.
# Usage: run_cpp.sh CONFORMANCE_BINARY CASES_JSON SERVER_BINARY
set -euo pipefail
runner=$1 cases=$2 server=$3
log=$(mktemp)
"$server" --listen 127.0.0.1:0 --telemetry "" > "$log" 2>&1 &
pid=$!
trap 'kill $pid 2>/dev/null; wait 2>/dev/null; rm -f "$log"' EXIT
for _ in $(seq 100); do
  address=$(sed -n 's/^culinarycut-server listening on //p' "$log")
  [ -n "$address" ] && break
  sleep 0.1
done
[ -n "${address:-}" ] || { echo "the server did not start:"; cat "$log"; exit 1; }
"$runner" "$cases" "$address"
