#!/usr/bin/env bash
# The certificate on a family of camera paths nobody tuned the board on (docs/cell-tree.md,
# "The family"): scripts/sched_family.py makes 12 paths from seed 7 (generated volumes only,
# so no ../shared; the constants were fitted on seed 1), scripts/sched_family_run.py runs each
# at 48x48 for 6 frames with the board as it ships and with `--stale-check off`, and fails when
# a frame fetches more than Max Work plus its budget, when the board's shadow of Max Work finds
# other fetches than the Max Work run, when the shadow breaks, or when the board keeps less
# than 90 % of the unchecked rule's saving over the paths where that saves 5 % or more (with
# the allowance at 2 % instead of 25 % it keeps 31.8 %, with the start overlap at 0.95 instead
# of 0.8 86.4 %). The runner is shown failing on a frame made to break the bound and on a
# board made to save nothing.
# Usage: sched_family_test.sh BUILD
set -u
build=${1:-build}
. "$(dirname "$0")/lib.sh"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

python3 scripts/sched_family.py --seed 7 --paths 12 --out "$tmp/fam" --max-bounces 5
python3 scripts/sched_family.py --seed 7 --paths 12 --out "$tmp/fam2" --max-bounces 5
same=1
for f in "$tmp"/fam/p*.json; do cmp -s "$f" "$tmp/fam2/${f##*/}" || same=0; done
if [ $same = 1 ] && diff <(cut -f1,3- "$tmp/fam/family.tsv") <(cut -f1,3- "$tmp/fam2/family.tsv") >/dev/null &&
    [ "$(wc -l < "$tmp/fam/family.tsv")" -eq 12 ]; then
    ok family_same_from_the_seed
else
    bad family_same_from_the_seed "two runs with seed 7 differ, or not 12 paths"
fi

out=$(python3 scripts/sched_family_run.py --cube5 "$build/cube5" --family "$tmp/fam" --size 48x48 --frames 6 \
    --min-kept 0.9 --json "$tmp/fam.json" 2>&1)
st=$?
if [ $st -eq 0 ] && grep -q '^family: 12 paths' <<<"$out"; then
    ok family_within_the_certificate_keeping_90_percent
else
    bad family_within_the_certificate_keeping_90_percent "exit $st" "$out"
fi
followed=$(python3 -c "import json,sys; print(sum(p['frames_followed'] for p in json.load(open(sys.argv[1]))['paths']))" "$tmp/fam.json" 2>/dev/null)
if [ "${followed:-0}" -ge 12 ]; then ok family_frames_followed; else bad family_frames_followed "only ${followed:-0} frames followed a schedule"; fi

# The runner's own checks, on the family's first 4 paths (path 1 saves unchecked).
mkdir "$tmp/few"
head -n 4 "$tmp/fam/family.tsv" > "$tmp/few/family.tsv"

# A cube5 whose first followed frame reports one fetch more than Max Work plus its budget.
cat > "$tmp/liar" <<LIAR
#!/usr/bin/env bash
"$PWD/$build/cube5" "\$@" | python3 -c '
import json, sys
d = json.load(sys.stdin)
for f in d["frames"]:
    if f.get("certificate"):
        f["fetches_celltree"] = f["fetches_maxwork"] + max(f["certificate"]["budget"] or 0, 0) + 1
        break
print(json.dumps(d))'
LIAR
chmod +x "$tmp/liar"
out=$(python3 scripts/sched_family_run.py --cube5 "$tmp/liar" --family "$tmp/few" --size 32x32 --frames 3 2>&1)
st=$?
if [ $st -eq 1 ] && grep -q 'PROBLEM: frame [0-9]*: [0-9]* fetches > Max Work' <<<"$out"; then
    ok family_runner_catches_a_broken_bound
else
    bad family_runner_catches_a_broken_bound "exit $st" "$out"
fi
# A cube5 whose followed frames save nothing: the family keeps 0 % and the runner says so.
cat > "$tmp/idle" <<IDLE
#!/usr/bin/env bash
"$PWD/$build/cube5" "\$@" | python3 -c '
import json, sys
d = json.load(sys.stdin)
for f in d["frames"]:
    if f.get("certificate"):
        f["fetches_celltree"] = f["fetches_maxwork"]
print(json.dumps(d))'
IDLE
chmod +x "$tmp/idle"
out=$(python3 scripts/sched_family_run.py --cube5 "$tmp/idle" --family "$tmp/few" --size 32x32 --frames 5 \
    --min-kept 0.9 2>&1)
st=$?
if [ $st -eq 1 ] && grep -q 'keeps 0.0% of the unchecked saving, below 90%' <<<"$out"; then
    ok family_runner_catches_a_lost_saving
else
    bad family_runner_catches_a_lost_saving "exit $st" "$out"
fi
summary
