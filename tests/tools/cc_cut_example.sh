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

"$cc_cut" "$scene" --quiet --particles --out "$out/run" || fail "cc-cut exited with $?"
[ -s "$out/run/steps.csv" ] || fail "no steps.csv"
[ -s "$out/run/summary.json" ] || fail "no summary.json"
head -n 1 "$out/run/steps.csv" | grep -q '^step,t_s,dt_s,knife_z_m,' || fail "bad steps.csv header"
[ "$(wc -l < "$out/run/steps.csv")" -gt 10 ] || fail "steps.csv has too few rows"
grep -q '"pieces"' "$out/run/summary.json" || fail "summary.json has no pieces"
grep -q '"dt_s"' "$out/run/summary.json" || fail "summary.json has no dt_s"
# particles.csv: a row per particle (as many as summary.json's pieces and crumbs hold), the cut's two
# pieces among the labels, and every final position near the food (finite, within a metre).
head -n 1 "$out/run/particles.csv" | grep -q '^rest_x_m,rest_y_m,rest_z_m,x_m,y_m,z_m,piece$' || fail "bad particles.csv header"
rows=$(($(wc -l < "$out/run/particles.csv") - 1))
grep -q "\"particles\": $rows," "$out/run/summary.json" || fail "particles.csv has $rows rows, not the summary's particle count"
awk -F, 'NR > 1 { seen[$7] = 1; for (i = 4; i <= 6; ++i) if (!($i > -1 && $i < 1)) bad = 1 }
         END { exit !(seen[0] && seen[1] && !bad) }' "$out/run/particles.csv" || fail "particles.csv lacks pieces 0 and 1 or has a stray position"
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
