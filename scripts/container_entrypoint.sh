#!/bin/sh
# The server image's entrypoint: container_entrypoint.sh SERVER_BINARY [FLAGS...]. Checks that every file a
# flag names (--tls-cert, --tls-key, --tls-client-ca, --token-file) can be read before starting the server,
# and otherwise says what to mount and how to make it, exiting 2 as the server does for bad flags.
set -eu
server=$1
shift
missing=""
previous=""
for arg in "$@"; do
  file=""
  case "$previous" in
    --tls-cert|--tls-key|--tls-client-ca|--token-file) file=$arg flag=$previous ;;
  esac
  case "$arg" in
    --tls-cert=*|--tls-key=*|--tls-client-ca=*|--token-file=*) file=${arg#*=} flag=${arg%%=*} ;;
  esac
  if [ -n "$file" ] && [ ! -r "$file" ]; then
    missing="$missing
  $flag $file"
  fi
  previous=$arg
done
if [ -n "$missing" ]; then
  cat >&2 <<EOF
culinarycut-server: not started: the container cannot read$missing
The image serves over TLS with bearer tokens: make a certificate and a token once with
  scripts/make_server_secrets.sh secrets
and mount them read only (docker compose up does, from ./secrets):
  docker run -p 127.0.0.1:50051:50051 \\
    -v "\$PWD/secrets/server.pem:/run/secrets/server.pem:ro" \\
    -v "\$PWD/secrets/server.key:/run/secrets/server.key:ro" \\
    -v "\$PWD/secrets/tokens.txt:/run/secrets/tokens.txt:ro" culinarycut-server
Or, without TLS, on the host's loopback only:
  docker run --network host culinarycut-server --listen 127.0.0.1:50051
See docs/deployment.md.
EOF
  exit 2
fi
exec "$server" "$@"
