# Sourced by the CLI test scripts: check NAME COMMAND... runs the command, counts a pass or a
# failure, and on failure prints the name and the command's output. Needs $work.
passes=0 failures=0
check() {
  local name=$1
  shift
  if "$@" >"$work/log" 2>&1; then passes=$((passes + 1)); else failures=$((failures + 1)); echo "FAILED: $name"; cat "$work/log"; fi
}
