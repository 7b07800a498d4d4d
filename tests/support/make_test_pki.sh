#!/usr/bin/env bash
# A throwaway PKI for the TLS tests: a CA, a server certificate for 127.0.0.1 / localhost and a
# client certificate, both signed by the CA, a second client certificate with the same subject as the
# first (client2: a different key, so a different certificate), and a token file with two tokens (alice, bob).
# Usage: make_test_pki.sh DIR
set -euo pipefail
dir="$1"
mkdir -p "$dir"
cd "$dir"
openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj "/CN=culinarycut test CA" \
  -keyout ca.key -out ca.pem 2>/dev/null
for name in server client client2; do
  subject="/CN=culinarycut test ${name%2}"
  openssl req -newkey rsa:2048 -nodes -subj "$subject" -keyout "$name.key" -out "$name.csr" 2>/dev/null
  printf 'subjectAltName=IP:127.0.0.1,DNS:localhost\n' > "$name.ext"
  openssl x509 -req -in "$name.csr" -CA ca.pem -CAkey ca.key -CAcreateserial -days 2 -extfile "$name.ext" \
    -out "$name.pem" 2>/dev/null
done
printf 'alice %s\nbob %s\n' "$(openssl rand -hex 24)" "$(openssl rand -hex 24)" > tokens.txt
chmod 600 ./*.key tokens.txt
