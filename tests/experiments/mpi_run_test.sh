#!/usr/bin/env bash
# The tissuebench CLI under mpirun: `mpirun -n 2 tissuebench run`
# writes each case once (rank 0), atomically (no staging folder left), with both
# ranks' peak memory, and the same top-surface field as one process to 1e-8.
# Usage: mpi_run_test.sh MPIEXEC TISSUEBENCH SOURCE_DIR
set -euo pipefail
mpiexec=$1 cli=$2 src=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
scenario="$src/tests/experiments/mpi_small.json"
"$cli" run "$scenario" --out "$tmp/np1" --quiet --mesh-cache "$tmp/cache"
"$mpiexec" -n 2 "$cli" run "$scenario" --out "$tmp/np2" --quiet --mesh-cache "$tmp/cache2" 2>"$tmp/np2.err"
# One writer: rank 0's summary line and nothing else (no rank repeats it).
if [ "$(grep -c . "$tmp/np2.err")" != 1 ] || ! grep -q "2 of 2 cases written" "$tmp/np2.err"; then
  echo "stderr under mpirun (expected rank 0's summary line only):"; cat "$tmp/np2.err"; exit 1
fi
if find "$tmp/np1" "$tmp/np2" -name '*.tmp*' | grep -q .; then echo "staging folders left behind"; exit 1; fi
/usr/bin/python3 - "$tmp" <<'PY'
import json, os, sys
import numpy as np
tmp = sys.argv[1]
for case in ("fem-p1", "fem-p2"):
    fields = []
    for n in (1, 2):
        folder = os.path.join(tmp, f"np{n}", "mpi-small", "mpi-small", case)
        data = np.genfromtxt(os.path.join(folder, "top_surface.csv"), delimiter=",", skip_header=1)
        fields.append(data[:, 4:7])
        ranks = json.load(open(os.path.join(folder, "timings.json")))["processes"]["ranks"]
        assert ranks == n, f"{case} np{n}: timings.json says {ranks} ranks"
    diff = np.linalg.norm(fields[1] - fields[0]) / np.linalg.norm(fields[0])
    print(f"{case}: np 2 against np 1, relative difference {diff:.2e}")
    assert diff < 1e-8, f"{case}: {diff}"
PY
