#!/usr/bin/env bash
# The block index of fpga/README.md ("The blocks and their files"): every path it names exists
# (a `*` stands for the vector sources), and every top-level block of fpga/rtl/ (a .vhd that is
# not a package or one of the ray queue's parts, rq_*) has a row; and each such block has one
# name: fpga/rtl/BLOCK.vhd, tb/tb_BLOCK.vhd, tb/tb_BLOCK_live.vhd, fpga/ref/c5ref_BLOCK.c,
# vectors/gen/vec_BLOCK.c and vectors/golden/BLOCK.* all exist, and the index names them.
# Usage: blocks_index_test.sh
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

# names ROOT INDEX: the files a top-level block of ROOT/fpga/rtl must have under its one name,
# missing from ROOT or not named in the index INDEX.
names() {
    local missing="" p blk f table
    table=$(sed -n '/<!-- blocks-index -->/,/<!-- \/blocks-index -->/p' "$2")
    for p in "$1"/fpga/rtl/*.vhd; do
        blk=$(basename "$p" .vhd)
        case $blk in *_pkg | rq_*) continue ;; esac
        for f in "tb/tb_$blk.vhd" "tb/tb_${blk}_live.vhd" "fpga/ref/c5ref_$blk.c" "vectors/gen/vec_$blk.c"; do
            [ -f "$1/$f" ] || missing+=" $f"
            grep -qF "\`$f\`" <<<"$table" || missing+=" ($f not in the index)"
        done
        compgen -G "$1/vectors/golden/$blk.*.hex" >/dev/null || missing+=" vectors/golden/$blk.*.hex"
        grep -qF "\`vectors/golden/$blk.*\`" <<<"$table" || missing+=" (vectors/golden/$blk.* not in the index)"
    done
    echo "$missing"
}

out=$(names . fpga/README.md)
[ -z "$out" ] && ok "blocks names: every block of fpga/rtl has its testbenches, reference, generator and golden files under its own name" ||
    bad "blocks names: files missing or not indexed" "missing:$out"

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
# ... and the name check can fail: a tree (empty files) where one block's reference is named
# otherwise, and the index without one testbench.
mkdir "$tmp/tree"
while read -r f; do mkdir -p "$tmp/tree/$(dirname "$f")" && : >"$tmp/tree/$f"; done \
    < <(git ls-files fpga/rtl tb fpga/ref vectors/gen vectors/golden 2>/dev/null || find fpga/rtl tb fpga/ref vectors/gen vectors/golden -type f)
mv "$tmp/tree/fpga/ref/c5ref_shade.c" "$tmp/tree/fpga/ref/c5ref_shading.c"
case $(names "$tmp/tree" fpga/README.md) in *"fpga/ref/c5ref_shade.c"*) ok "blocks names: a block's file under another name is found" ;;
    *) bad "blocks names: the check passed c5ref_shading.c for the block shade" ;; esac
sed 's#`tb/tb_interp_live.vhd`#`tb/tb_interp_live2.vhd`#' fpga/README.md >"$tmp/unindexed.md"
case $(names . "$tmp/unindexed.md") in *"tb/tb_interp_live.vhd not in the index"*) ok "blocks names: a file the index does not name is found" ;;
    *) bad "blocks names: the check passed an index without tb/tb_interp_live.vhd" ;; esac
summary
