#!/usr/bin/env bash
# Installs the Debian/Ubuntu packages of a profile, only those missing; safe to run again.
# Uses sudo when not root.
#   setup-deps.sh demo        scripts/deps/demo.txt: build/cube5 and `make demo` (the Makefile)
#   setup-deps.sh test        demo.txt and scripts/deps/test.txt: `make test` (the Makefile)
#   setup-deps.sh PKG...      those packages (bench-peer.sh, fpga-report.sh, results.sh and
#                             accuracy.sh install their own extras this way)
set -euo pipefail
deps="$(dirname "$0")/deps"
list() { sed -e 's/#.*//' "$@" | tr -s ' \t' '\n' | sed '/^$/d'; }
case "${1:-demo}" in
    demo) mapfile -t pkgs < <(list "$deps/demo.txt") ;;
    test) mapfile -t pkgs < <(list "$deps/demo.txt" "$deps/test.txt") ;;
    *) pkgs=("$@") ;;
esac
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "setup: installing ${missing[*]}" >&2
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
