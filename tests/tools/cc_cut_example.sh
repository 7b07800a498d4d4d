#!/bin/sh
# Runs cc-cut on a scene and checks its exit code and outputs; then that a bad scene gives exit 2.
# Usage: cc_cut_example.sh CC_CUT SCENE.json
set -u
cc_cut="$1"
scene="$2"
out="$(mktemp -d "${TMPDIR:-/tmp}/cc_cut_example.XXXXXX")" || exit 1
trap 'rm -rf "$out"' EXIT

fail() { echo "cc_cut_example: $*" >&2; exit 1; }

"$cc_cut" "$scene" --quiet --out "$out/run" || fail "cc-cut exited with $?"
[ -s "$out/run/steps.csv" ] || fail "no steps.csv"
[ -s "$out/run/summary.json" ] || fail "no summary.json"
head -n 1 "$out/run/steps.csv" | grep -q '^step,t_s,dt_s,knife_z_m,' || fail "bad steps.csv header"
[ "$(wc -l < "$out/run/steps.csv")" -gt 10 ] || fail "steps.csv has too few rows"
grep -q '"pieces"' "$out/run/summary.json" || fail "summary.json has no pieces"
grep -q '"dt_s"' "$out/run/summary.json" || fail "summary.json has no dt_s"

printf '{"knife": {"descent_speed_m_s": -1}}\n' > "$out/bad.json"
"$cc_cut" "$out/bad.json" --quiet --out "$out/bad" 2> "$out/bad.err"
code=$?
[ "$code" -eq 2 ] || fail "a bad scene exited with $code, not 2"
grep -q 'knife.descent_speed_m_s' "$out/bad.err" || fail "the error does not name the field"
"$cc_cut" "$out/missing.json" --quiet --out "$out/bad" 2> /dev/null
code=$?
[ "$code" -eq 2 ] || fail "a missing scene exited with $code, not 2"
echo "cc_cut_example: ok"
