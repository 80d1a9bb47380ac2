#!/usr/bin/env bash
# Installs the Debian/Ubuntu packages of a profile, only those missing; safe to run again.
# Uses sudo when not root.
#   setup-deps.sh demo        scripts/deps/demo.txt: build/cube5 and `make demo` (the Makefile)
#   setup-deps.sh test        demo.txt and scripts/deps/test.txt: `make test` (the Makefile)
#   setup-deps.sh PKG...      those packages (bench-peer.sh, fpga-report.sh, results.sh and
#                             accuracy.sh install their own extras this way)
#   setup-deps.sh --list demo|test   prints the profile's packages, one a line (tests/deps_test.sh)
set -euo pipefail
deps="$(dirname "$0")/deps"
list() { sed -e 's/#.*//' "$@" | tr -s ' \t' '\n' | sed '/^$/d'; }
profile() { # demo|test: the package lists it installs
    case $1 in demo) echo "$deps/demo.txt" ;; test) echo "$deps/demo.txt $deps/test.txt" ;; *) return 1 ;; esac
}
if [ "${1:-}" = --list ]; then
    files=$(profile "${2:-}") || { echo "setup-deps: --list demo|test" >&2; exit 2; }
    # shellcheck disable=SC2086
    list $files
    exit 0
fi
if files=$(profile "${1:-demo}"); then
    # shellcheck disable=SC2086
    mapfile -t pkgs < <(list $files)
else
    pkgs=("$@")
fi
missing=()
for p in "${pkgs[@]}"; do
  [ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null)" = "install ok installed" ] || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "setup: installing ${missing[*]}" >&2
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
