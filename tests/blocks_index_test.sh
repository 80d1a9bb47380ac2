#!/usr/bin/env bash
# The block index of fpga/README.md ("The blocks and their files"): every path it names exists
# (a `*` stands for the vector sources), and every top-level block of fpga/rtl/ (a .vhd that is
# not a package or one of the ray queue's parts, rq_*) has a row. Usage: blocks_index_test.sh
set -u
cd "$(dirname "$0")/.."
. tests/lib.sh

# check FILE: the index table of FILE (between the blocks-index markers) against the tree.
check() {
    local table missing="" rows p blk
    table=$(sed -n '/<!-- blocks-index -->/,/<!-- \/blocks-index -->/p' "$1" | grep '^| [a-z_]* |' | tail -n +2)
    rows=$(cut -d'|' -f2 <<<"$table" | tr -d ' ')
    for p in $(grep -o '`[^`]*`' <<<"$table" | tr -d '`' | grep '/'); do
        # shellcheck disable=SC2086 # a glob on purpose
        compgen -G "$p" >/dev/null || missing+=" $p"
    done
    for p in fpga/rtl/*.vhd; do
        blk=$(basename "$p" .vhd)
        case $blk in *_pkg | rq_*) continue ;; esac
        grep -qx "$blk" <<<"$rows" || missing+=" (no row for $blk)"
    done
    [ -n "$rows" ] || missing+=" (no table)"
    echo "$missing"
}

out=$(check fpga/README.md)
[ -z "$out" ] && ok "blocks index: every path exists and every block of fpga/rtl has a row" ||
    bad "blocks index: fpga/README.md" "missing:$out"

# The check can fail: a page with a wrong path, and one without a block's row.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
sed 's#fpga/ref/c5ref_shade.c#fpga/ref/c5ref_shading.c#' fpga/README.md >"$tmp/wrong.md"
case $(check "$tmp/wrong.md") in *c5ref_shading.c*) ok "blocks index: a wrong path is found" ;;
    *) bad "blocks index: the check passed a path that does not exist" ;; esac
grep -v '^| traverse |' fpga/README.md >"$tmp/norow.md"
case $(check "$tmp/norow.md") in *"no row for traverse"*) ok "blocks index: a block without a row is found" ;;
    *) bad "blocks index: the check passed an index without traverse" ;; esac
summary
