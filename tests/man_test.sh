#!/usr/bin/env bash
# The manual pages (man/*.1): each renders without a groff warning, carries VERSION, and
# lists every option its tool's --help lists (for cube5, every command has a section that
# lists every option of `cube5 COMMAND --help`). Usage: man_test.sh BUILD
set -u
cd "$(dirname "$0")/.."
. tests/lib.sh
build=${1:-build}
version=$(cat VERSION)

# The page as plain text: no hyphenation, long lines, so an option is never split.
render() { groff -man -Tascii -P-cbou -rHY=0 -rLL=250n "$1" 2>/dev/null; }

# The options a --help text names: -x or --name after a blank, '[', '|' or '('. Options of
# other programs (render_vtk.py --raw) or other commands ('cube5 render SCENE --volume FILE')
# named in the prose are not the tool's.
options() {
    sed -E -e 's/[A-Za-z0-9_]+\.py --?[a-z][a-z0-9-]*//g' -e "s/'[^']*'//g" |
        grep -oE '(^|[[:space:][|(])--?[a-z][a-z0-9-]*' | sed 's/^[^-]*//' | sort -u
}

# check NAME PAGE_TEXT HELP_TEXT: every option of the help in the page text.
check() {
    local missing="" o n
    for o in $(options <<<"$3"); do
        grep -qE -- "(^|[^A-Za-z0-9_-])$o([^A-Za-z0-9_-]|$)" <<<"$2" || missing+=" $o"
    done
    n=$(options <<<"$3" | wc -l)
    if ! grep -q '^usage: ' <<<"$3"; then
        bad "man: $1" "its --help printed no usage: $3"
    elif [ -n "$missing" ]; then
        bad "man: $1" "options of --help missing from the page:$missing"
    else
        ok "man: $1 lists the $n options of its --help"
    fi
}

for page in man/cube5.1 man/cube5ctl.1 man/cube5-board.1; do
    warn=$(groff -man -Tutf8 -ww -z "$page" 2>&1)
    [ -z "$warn" ] && ok "man: $page renders without a warning" || bad "man: $page warns" "$warn"
    grep -q "^\.TH .* \"cube5 $version\"" "$page" && ok "man: $page is of version $version" ||
        bad "man: $page" "its .TH does not say \"cube5 $version\" (VERSION)"
done

# The command sections are made from the option tables: the page must be what they make now,
# and a page that differs (one help line changed) must fail that check.
if out=$(bash scripts/man-commands.sh "$build/cube5" man/cube5.1 --check 2>&1); then
    ok "man: man/cube5.1's command sections are those the option tables make"
else
    bad "man: man/cube5.1 is stale" "$out"
fi
stale=$(mktemp -d)
sed 's/^worker threads 1\.\.64/worker threads 1..63/' man/cube5.1 >"$stale/cube5.1"
if cmp -s man/cube5.1 "$stale/cube5.1"; then
    bad "man: the stale-page check" "the sample edit did not apply (cast's --threads help moved?)"
elif bash scripts/man-commands.sh "$build/cube5" "$stale/cube5.1" --check 2>/dev/null; then
    bad "man: the stale-page check passed a page whose cast --threads line was changed"
else
    ok "man: the stale-page check finds a changed help line"
fi
rm -rf "$stale"

# A sample page that lacks an option of its help must fail the check.
out=$(check sample "  --alpha A" $'usage: sample [--alpha A] [--beta]')
case $out in FAIL*--beta*) ok "man: the option check finds a missing option";;
    *) bad "man: the option check passed a page without --beta" "$out";; esac

for tool in cube5ctl cube5-board; do
    check "$tool" "$(render "man/$tool.1")" "$("$build/$tool" --help 2>&1)"
done

text=$(render man/cube5.1)
check "cube5 (top level)" "$text" "$("$build/cube5" --help 2>&1)"
# The commands are the first word of the indented lines of `cube5 --help` (help is the
# top-level section of its own).
for cmd in $("$build/cube5" --help 2>&1 | sed -n 's/^  \([a-z]\+\) .*/\1/p'); do
    [ "$cmd" = help ] && continue
    # the command's section: from its heading to the next heading
    section=$(awk -v h="^   cube5 $cmd( |\$)" '$0 ~ h {on = 1; print; next} on && /^(   )?[A-Za-z]/ {on = 0} on' <<<"$text")
    if [ -z "$section" ]; then
        bad "man: cube5 $cmd" "no section 'cube5 $cmd' in man/cube5.1"
        continue
    fi
    check "cube5 $cmd" "$section" "$("$build/cube5" "$cmd" --help 2>&1)"
done
summary
