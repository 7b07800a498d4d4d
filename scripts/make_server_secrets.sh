#!/usr/bin/env bash
# Makes what a server needs to serve over TLS with bearer tokens (the server image's default), with openssl:
#   ca.pem, ca.key          a private CA (ca.key stays here: it is never mounted); clients trust ca.pem
#   server.pem, server.key  the server's certificate, signed by the CA, for localhost, 127.0.0.1, ::1,
#                           `server` (the compose service's name) and every NAME given
#   tokens.txt              the server's --token-file: one line "client <token>"
#   client.token            that token alone, for clients (CULINARYCUT_TOKEN)
# Usage: make_server_secrets.sh DIR [NAME...]   (NAME: another DNS name or IP address clients connect to)
# DIR is made 0700, so only you reach the files; the files themselves are readable by anyone who reaches
# them, because the container's user (not you) reads them through the mounts. Refuses to overwrite.
set -euo pipefail
if [ $# -lt 1 ]; then
  echo "usage: $0 DIR [NAME...]  (NAME: a DNS name or IP address clients use to reach the server)" >&2
  exit 2
fi
dir=$1
shift
days=365
for file in ca.key server.key tokens.txt; do
  if [ -e "$dir/$file" ]; then
    echo "$0: $dir/$file exists: remove the old secrets or choose another folder" >&2
    exit 1
  fi
done
mkdir -p "$dir"
chmod 700 "$dir"
cd "$dir"

san="DNS:localhost,DNS:server,IP:127.0.0.1,IP:::1"
for name in "$@"; do
  # an IPv4 or IPv6 address goes in as IP:, anything else as DNS:
  if [[ $name =~ ^[0-9.]+$ || $name == *:* ]]; then san+=",IP:$name"; else san+=",DNS:$name"; fi
done

openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -days "$days" \
  -subj "/CN=CulinaryCut CA" -addext "basicConstraints=critical,CA:TRUE" \
  -addext "keyUsage=critical,keyCertSign,cRLSign" -keyout ca.key -out ca.pem 2>/dev/null
openssl req -new -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -subj "/CN=culinarycut-server" \
  -keyout server.key -out server.csr 2>/dev/null
printf 'subjectAltName=%s\nbasicConstraints=CA:FALSE\nextendedKeyUsage=serverAuth\n' "$san" > server.ext
openssl x509 -req -in server.csr -CA ca.pem -CAkey ca.key -set_serial "0x$(openssl rand -hex 16)" \
  -days "$days" -extfile server.ext -out server.pem 2>/dev/null
rm -f server.csr server.ext
token=$(openssl rand -hex 32)
printf 'client %s\n' "$token" > tokens.txt
printf '%s\n' "$token" > client.token
chmod 600 ca.key
chmod 644 ca.pem server.pem server.key tokens.txt client.token
echo "make_server_secrets: $dir holds ca.pem, server.pem, server.key (for $san), tokens.txt and client.token;" \
     "valid $days days"
