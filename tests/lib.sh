# Shared by the shell test suites (sourced): the ok / FAIL lines and the closing
# "SUMMARY passed=N failed=N" that tests/run.sh adds up (summary ends the suite, with
# status 0 only when nothing failed).
passed=0 failed=0
ok() { echo "ok   $1"; passed=$((passed + 1)); }
bad() { echo "FAIL $1"; shift; printf '    %s\n' "$@"; failed=$((failed + 1)); }
summary() { echo "SUMMARY passed=$passed failed=$failed"; [ "$failed" -eq 0 ]; exit; }
# Whether BIN was built with AddressSanitizer (linked to libasan). ldd's output is captured
# first: under pipefail, `ldd BIN | grep -q` fails whenever grep quits before ldd has written
# everything (ldd dies of SIGPIPE; tests/pipefail_lint_test.sh keeps that pattern out).
links_asan() { local libs; libs=$(ldd "$1" 2>/dev/null) && grep -q libasan <<<"$libs"; }
