#!/usr/bin/env bash
# The main job: installs and builds, starts a server, runs the smoke benchmark suite with the
# scripted oracle (the default policy) and prints its results table. Stops the server after.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/install_deps.sh"
"$root/scripts/build.sh"

log="$(mktemp -t culinarycut-server.XXXXXX.log)"
"$root/build/server/culinarycut-server" --listen 127.0.0.1:0 --telemetry tcp://127.0.0.1:0 >"$log" 2>&1 &
server_pid=$!
trap 'kill -TERM $server_pid 2>/dev/null; wait $server_pid 2>/dev/null || true' EXIT

address=""
for _ in $(seq 1 100); do
  address="$(sed -n 's/^culinarycut-server listening on //p' "$log")"
  [ -n "$address" ] && break
  kill -0 $server_pid 2>/dev/null || { echo "run_main: the server exited:"; cat "$log"; exit 1; }
  sleep 0.1
done
[ -n "$address" ] || { echo "run_main: the server did not start within 10 s:"; cat "$log"; exit 1; }
echo "run_main: server at $address (log: $log)"

out="$(mktemp -d -t culinarycut-smoke.XXXXXX)"
"$root/.venv/bin/culinarycut" bench run smoke --policy oracle --server "$address" --workers 2 --out "$out/run"
"$root/.venv/bin/culinarycut" bench report "$out/run"
