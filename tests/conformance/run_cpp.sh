#!/usr/bin/env bash
# Starts a server on a free loopback port and runs the C++ conformance runner against it.
# Usage: run_cpp.sh CONFORMANCE_BINARY CASES_JSON SERVER_BINARY
set -euo pipefail
runner=$1 cases=$2 server=$3
source "$(dirname "$0")/../support/start_server.sh"
log=$(mktemp)
SERVER_PID=""
trap '[ -n "$SERVER_PID" ] && kill $SERVER_PID 2>/dev/null; wait 2>/dev/null; rm -f "$log"' EXIT
start_server "$server" "$log"
"$runner" "$cases" "$SERVER_ADDRESS"
