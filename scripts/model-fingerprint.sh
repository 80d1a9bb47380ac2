#!/usr/bin/env bash
# The board model's fingerprint: 16 hex digits that change when any bit the model produces
# changes. It is the SHA-256 of the CRC-32s in the manifest of a small fixed vector set
# (`cube5 vectors`, docs/vectors.md): per built-in scene the frame buffer, the packet trace and
# the DSP RAM, and every block's vector file (packet codec, ray queue, Cell Tree, scheduler,
# datapath). make results and make accuracy record it beside what they generate
# (docs/results/model-fingerprint, docs/accuracy/model-fingerprint); tests/fingerprint_test.sh
# fails when the model's fingerprint is no longer the one recorded.
# Usage: model-fingerprint.sh [BUILD | --manifest FILE]   (about 2 s)
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = --manifest ]; then
    manifest=$2
else
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    "${1:-build}/cube5" vectors --out "$tmp/v" --seed 1 --count 128 --size 64x64 --cells 2x2x2 >/dev/null
    manifest=$tmp/v/manifest.json
fi
python3 - "$manifest" <<'PY' | LC_ALL=C sort | sha256sum | cut -c1-16
import json, sys
m = json.load(open(sys.argv[1]))
for s in m["scenes"]:
    for k in ("frame_buffer", "packet_trace", "dsp_ram"):
        print(s["scene"], k, s[k])
for f in m["files"]:
    print(f["file"], f["checksum"])
PY
