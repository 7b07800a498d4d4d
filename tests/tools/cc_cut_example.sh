#!/bin/sh
# Runs cc-cut on a scene and checks its exit code and outputs; then that bad scenes give exit 2 and
# a message naming the field.
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
# The resolved scene holds the food's pose as the server resolves it: a non-empty quaternion.
grep -q '"quaternion": \[$' "$out/run/summary.json" || fail "summary.json has no resolved food pose"

# Bad input: exit code 2 and a message naming the field, in cc-cut's blocks and in the scene block.
expect_bad() {  # JSON FIELD
  printf '%s\n' "$1" > "$out/bad.json"
  "$cc_cut" "$out/bad.json" --quiet --out "$out/bad" 2> "$out/bad.err"
  code=$?
  [ "$code" -eq 2 ] || fail "bad scene $1 exited with $code, not 2"
  grep -qF "$2" "$out/bad.err" || fail "the error for $1 does not name $2: $(cat "$out/bad.err")"
}
expect_bad '{"knife": {"descent_speed_m_s": -1}}' 'knife.descent_speed_m_s'
expect_bad '{"scene": {"objects": [{"food": "cucumber", "scale": "big"}]}}' 'scene.objects[0].scale'
expect_bad '{"scene": {"effects": {"mpm": true}, "objects": [{"food": "cucumber", "scale": 20}]}}' 'scene.objects[0].scale'
expect_bad '{"scene": {"objects": [{"food": "cucumber", "colour": "green"}]}}' 'scene.objects[0].colour'
"$cc_cut" "$out/missing.json" --quiet --out "$out/bad" 2> /dev/null
code=$?
[ "$code" -eq 2 ] || fail "a missing scene exited with $code, not 2"
echo "cc_cut_example: ok"
