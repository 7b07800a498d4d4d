# Sourced by test scripts: start_server BINARY LOG [SERVER ARGS...] starts a culinarycut-server on a free
# loopback port, waits for it to print its address, and sets SERVER_PID and SERVER_ADDRESS (returns 1 if it
# does not start).
start_server() {
  local binary=$1 log=$2
  shift 2
  "$binary" --listen 127.0.0.1:0 --telemetry "" "$@" > "$log" 2>&1 &
  SERVER_PID=$!
  SERVER_ADDRESS=""
  for _ in $(seq 100); do
    SERVER_ADDRESS=$(sed -n 's/^culinarycut-server listening on //p' "$log")
    [ -n "$SERVER_ADDRESS" ] && return 0
    sleep 0.1
  done
  echo "the server did not start:"
  cat "$log"
  return 1
}
