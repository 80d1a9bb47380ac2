#!/usr/bin/env bash
# The generated docs record the board model they came from (scripts/model-fingerprint.sh):
# docs/results/ (make results) and docs/accuracy/ (make accuracy) must carry the fingerprint
# of the model as built, else their figures may be stale. Also shows that the fingerprint
# moves when one bit of the model's output moves. Usage: fingerprint_test.sh BUILD
set -u
build=${1:-build}
. "$(dirname "$0")/lib.sh"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

if ! now=$(bash scripts/model-fingerprint.sh "$build" 2>"$tmp/err") || [ -z "$now" ]; then
    bad model_fingerprint "scripts/model-fingerprint.sh $build failed" "$(cat "$tmp/err")"
    summary
fi
for d in results accuracy; do
    f=docs/$d/model-fingerprint
    rec=$(cat "$f" 2>/dev/null)
    if [ "$rec" = "$now" ]; then
        ok "docs_${d}_current"
    else
        bad "docs_${d}_current" "$f says the model was '${rec:-missing}'; the model as built is $now:" \
            "its bits changed since docs/$d/ was generated: run make $d and commit the result"
    fi
done
if grep -q "fingerprint \`$(cat docs/results/model-fingerprint 2>/dev/null)\`" docs/results/README.md; then
    ok results_readme_names_fingerprint
else
    bad results_readme_names_fingerprint "docs/results/README.md does not state docs/results/model-fingerprint"
fi

# One CRC of the fixed case changed (a frame buffer bit, say) gives another fingerprint.
python3 - vectors/golden/manifest.json "$tmp/m.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
c = m["scenes"][0]["frame_buffer"]
m["scenes"][0]["frame_buffer"] = c[:-1] + "%x" % (int(c[-1], 16) ^ 1)
json.dump(m, open(sys.argv[2], "w"))
PY
a=$(bash scripts/model-fingerprint.sh --manifest vectors/golden/manifest.json)
b=$(bash scripts/model-fingerprint.sh --manifest "$tmp/m.json")
if [ -n "$a" ] && [ -n "$b" ] && [ "$a" != "$b" ]; then ok fingerprint_sees_one_bit; else bad fingerprint_sees_one_bit "$a and $b"; fi
summary
