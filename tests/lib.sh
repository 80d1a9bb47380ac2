# Shared by the shell test suites (sourced): the ok / FAIL lines and the closing
# "SUMMARY passed=N failed=N" that tests/run.sh adds up (summary ends the suite, with
# status 0 only when nothing failed).
passed=0 failed=0
ok() { echo "ok   $1"; passed=$((passed + 1)); }
bad() { echo "FAIL $1"; shift; printf '    %s\n' "$@"; failed=$((failed + 1)); }
summary() { echo "SUMMARY passed=$passed failed=$failed"; [ "$failed" -eq 0 ]; exit; }
