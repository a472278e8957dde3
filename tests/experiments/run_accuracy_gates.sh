#!/usr/bin/env bash
# CI accuracy gates: runs the gates' experiment twice and checks every
# gate of experiments/accuracy_gates.json, printing measured beside threshold.
#   run_accuracy_gates.sh TISSUEBENCH_CLI SOURCE_DIR
set -euo pipefail
cli=$1
root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$cli" run "$root/experiments/gates.json" --out "$tmp/first" --quiet
"$cli" run "$root/experiments/gates.json" --out "$tmp/second" --quiet
/usr/bin/python3 "$root/analysis/gates.py" "$tmp/first/gates" "$root/experiments/accuracy_gates.json" \
  --repeat "$tmp/second/gates"
