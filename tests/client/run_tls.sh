#!/usr/bin/env bash
# Makes a throwaway PKI, starts a server with TLS and bearer tokens, and runs the C++ TLS client test.
# Usage: run_tls.sh TLS_CLIENT_BINARY SERVER_BINARY
set -euo pipefail
runner=$1 server=$2
here="$(cd "$(dirname "$0")" && pwd)"
source "$here/../support/start_server.sh"
pki=$(mktemp -d)
log="$pki/server.log"
SERVER_PID=""
trap '[ -n "$SERVER_PID" ] && kill $SERVER_PID 2>/dev/null; wait 2>/dev/null; rm -rf "$pki"' EXIT
bash "$here/../support/make_test_pki.sh" "$pki"
start_server "$server" "$log" --tls-cert "$pki/server.pem" --tls-key "$pki/server.key" --token-file "$pki/tokens.txt"
"$runner" "$SERVER_ADDRESS" "$pki"
