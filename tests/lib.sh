# Shared by the shell test suites (sourced): the ok / FAIL lines and the closing
# "SUMMARY passed=N failed=N" that tests/run.sh adds up (summary ends the suite, with
# status 0 only when nothing failed).
passed=0 failed=0
ok() { echo "ok   $1"; passed=$((passed + 1)); }
bad() { echo "FAIL $1"; shift; printf '    %s\n' "$@"; failed=$((failed + 1)); }
summary() { echo "SUMMARY passed=$passed failed=$failed"; [ "$failed" -eq 0 ]; exit; }
# json_field FILE EXPR: a Python expression over the JSON object d of FILE, printed.
json_field() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print($2)" "$1"; }
# Whether BIN was built with AddressSanitizer (linked to libasan). ldd's output is captured
# first: under pipefail, `ldd BIN | grep -q` fails whenever grep quits before ldd has written
# everything (ldd dies of SIGPIPE; tests/pipefail_lint_test.sh keeps that pattern out).
links_asan() { local libs; libs=$(ldd "$1" 2>/dev/null) && grep -q libasan <<<"$libs"; }
# judge NAME WANT STATUS ERR PATTERN: ok when the exit status is WANT and the ERE PATTERN
# (if any) is in ERR; a failure's ERR must also be one line "TOOL: error: ..." (TOOL is
# $judge_tool, default cube5). Returns 1 after reporting the first problem, 0 unreported,
# so a suite can add its own checks before calling ok.
judge() {
    local name=$1 want=$2 status=$3 err=$4 pat=$5
    if [ "$status" -ne "$want" ]; then
        bad "$name" "exit $status, expected $want (124: did not end in time)" "$err"
    elif [ -n "$pat" ] && ! grep -qE -- "$pat" <<<"$err"; then
        bad "$name" "stderr lacks /$pat/" "$err"
    elif [ "$want" -ne 0 ] && [ "$(wc -l <<<"$err")" -ne 1 ]; then
        bad "$name" "error is not one line" "$err"
    elif [ "$want" -ne 0 ] && ! grep -q "^${judge_tool:-cube5}: error: " <<<"$err"; then
        bad "$name" "error does not read '${judge_tool:-cube5}: error: ...'" "$err"
    else
        return 0
    fi
    return 1
}
# leftovers DIR: the temporaries of common/atomic_file.h (".NAME.tmp-...") left in DIR.
leftovers() { find "$1" -name '.*.tmp-*' 2>/dev/null; }
