#!/usr/bin/env bash
# Two-sided suite gates (analysis/suite_gates.py): runs experiments/suite.json at the
# small level experiments/suite_gates.json states (its "overrides", passed as --set;
# its "skip_scenarios", the suite's larger sizes, passed as --skip-scenario)
# and checks every case's field, error, probes, tool forces and beads against the
# committed values. To re-record after an intended change:
#   run_suite_gates.sh TISSUEBENCH SOURCE_DIR --record COMMIT
set -euo pipefail
cli=$1
root=$2
gates="$root/experiments/suite_gates.json"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mapfile -t settings < <(/usr/bin/python3 -c '
import json, sys
gates = json.load(open(sys.argv[1]))
for key, value in gates["overrides"]:
    print("--set"); print(f"{key}={json.dumps(value)}")
for name in gates.get("skip_scenarios", {}):
    print("--skip-scenario"); print(name)' "$gates")
# Exit 1: some case failed, which the suite expects of a few (the gates compare the
# failed cases with the committed list); anything else stops here.
status=0
"$cli" run "$root/experiments/suite.json" --out "$tmp" --quiet --no-mesh-output --mesh-cache "$tmp/cache" \
  "${settings[@]}" || status=$?
if [ "$status" -gt 1 ]; then echo "run_suite_gates: tissuebench run exited $status" >&2; exit "$status"; fi
if [ "${3:-}" = "--record" ]; then
  /usr/bin/python3 "$root/analysis/suite_gates.py" record "$tmp/suite" "$gates" --commit "$4"
else
  /usr/bin/python3 "$root/analysis/suite_gates.py" check "$tmp/suite" "$gates"
fi
