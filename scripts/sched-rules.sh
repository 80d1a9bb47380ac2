#!/usr/bin/env bash
# The split rules on the Figure 6 cases (docs/results/cell-tree-studies.md, "The rules against the best known schedule"):
# per case the fetches the board makes following each rule's schedule (paper, rollout,
# bounded, window), Max Work's, the schedule lengths, the best known schedule and the proven
# bound of the tree, and the DSP's operations of the window rule. Real volumes replace the stand-ins
# when ../shared/data/volumes holds them (CThead for brain_mirrors, lobster for
# lobster_tunnel). Prints a markdown table; the raw JSON goes to BUILD/sched-rules/.
#   bash scripts/sched-rules.sh [BUILD]
set -euo pipefail
BUILD=${1:-build}
CUBE5="$BUILD/cube5"
RAW="$BUILD/sched-rules"
VOL=../shared/data/volumes
mkdir -p "$RAW"
cases=()
for s in brain_mirrors clouds_lake lobster_tunnel; do
  for c in 2 3; do cases+=("$s|$c|$s|"); done
done
for c in 2 3; do
  [ -f "$VOL/CThead_256x256x113_uint8.raw" ] && cases+=("CThead|$c|brain_mirrors|$VOL/CThead_256x256x113_uint8.raw")
  [ -f "$VOL/lobster_301x324x56_uint8.raw" ] && cases+=("lobster|$c|lobster_tunnel|$VOL/lobster_301x324x56_uint8.raw")
done
for k in "${cases[@]}"; do
  IFS='|' read -r name c scene vol <<<"$k"
  args=("$scene" --cells "$c" --still --frames 2 --size 256x256)
  [ -n "$vol" ] && args+=(--volume "$vol")
  for rule in paper rollout bounded window; do
    states=0 walk=0
    [ "$rule" = window ] && states=200000 walk=500 # the bounds and the best known once per case
    echo "sched-rules: cube5 schedule ${args[*]} --split $rule --exact-states $states --local-walk $walk" >&2
    "$CUBE5" schedule "${args[@]}" --split "$rule" --exact-states "$states" --local-walk "$walk" --json \
        >"$RAW/${name}_c${c}_$rule.json"
  done
done
echo "sched-rules: cube5 schedule brain_mirrors --cells 3 --size 256x256 (camera path)" >&2
for rule in paper bounded window; do
  "$CUBE5" schedule brain_mirrors --cells 3 --size 256x256 --split "$rule" --exact-states 0 --stale-check off --json >"$RAW/anim_c3_$rule.json"
done
python3 - "$RAW" "${cases[@]}" <<'PY'
import json, sys
raw, cases = sys.argv[1], sys.argv[2:]
def load(n): return json.load(open(f"{raw}/{n}.json"))
rules = ("paper", "rollout", "bounded", "window")
print("| case | cells | Max Work | paper | rollout | bounded | window | loads paper / rollout / bounded / window | best known | optimum | proven bound | window over best known | window DSP ops (us at 255 MIPS) |")
print("|---|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|")
for k in cases:
    name, c = k.split("|")[:2]
    r = {rule: load(f"{name}_c{c}_{rule}")["frames"][1] for rule in rules}
    b = r["window"]
    best = b["optimum"] or b["best_known"]
    lens = b["schedule_len"]
    over = 100.0 * (b["fetches_celltree"] - best) / best if best else float("nan")
    print(f"| {name} | {int(c)**3} | {b['fetches_maxwork']} | " + " | ".join(str(r[x]['fetches_celltree']) for x in rules) +
          f" | {' / '.join(str(lens[x]) for x in rules)} | "
          f"{b['best_known']} | {b['optimum'] if b['optimum'] is not None else '-'} | {b['lower_bound']} | {over:+.1f}% | "
          f"{b['dsp_ops_schedule']:,} ({b['dsp_us_at_255mips']['schedule']:.0f}){' gave up' if b['bounded_gave_up'] else ''}"
          f"{', paper' if b['bounded_fell_back'] else ''} |")
print()
for rule in ("paper", "bounded", "window"):
    s = load(f"anim_c3_{rule}")["scheduled_frames"]
    print(f"camera path brain_mirrors 1/27, frames 1..7, {rule}: {s['fetches_celltree']} fetches against Max Work's "
          f"{s['fetches_maxwork']} ({s['reduction_pct']:.1f}% fewer)")
PY
