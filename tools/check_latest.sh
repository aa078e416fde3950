#!/usr/bin/env bash
# The drift check: install the newest releases pyproject.toml's ranges admit (no lock) into a
# fresh virtual environment and run the test suite there, so an upstream release that breaks
# rcm-pin is seen before the lock moves onto it. Non-blocking in .ci/run (it reports, CI's
# verdict is the locked run's); run it by hand before `bash tools/lock.sh`:
#
#     bash tools/check_latest.sh        # exit status: pytest's
#
# It prints the packages whose newest release differs from requirements/lock.txt and the
# failing tests; pytest's own output goes to $RCM_PIN_LATEST_LOG (default: a temporary file).
set -uo pipefail
cd "$(dirname "$0")/.."
export MPLBACKEND=Agg PYTHONDONTWRITEBYTECODE=1
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
log="${RCM_PIN_LATEST_LOG:-$tmp/pytest.log}"
python3 -m venv "$tmp/venv"
if ! "$tmp/venv/bin/pip" install -q --upgrade -e ".[test]" >"$tmp/pip.log" 2>&1; then
  echo "latest versions: the install failed"; tail -n 20 "$tmp/pip.log"; exit 1
fi
"$tmp/venv/bin/python" - requirements/lock.txt <<'PY'
import re, sys
from importlib import metadata

def norm(name):
    return re.sub(r"[-_.]+", "-", name).lower()

locked = {}
for line in open(sys.argv[1]):
    m = re.match(r"([A-Za-z0-9_.-]+)(?:\[[^\]]*\])?==([^ ;]+)", line)
    if m:
        locked.setdefault(norm(m[1]), set()).add(m[2])
drift = []
for dist in metadata.distributions():
    name = norm(dist.metadata["Name"])
    if name in locked and dist.version not in locked[name]:
        drift.append(f"{name} {'/'.join(sorted(locked[name]))} -> {dist.version}")
print("latest versions: " + (", ".join(sorted(drift)) if drift else "the same as the lock"))
PY
"$tmp/venv/bin/python" -m pytest -q -p no:cacheprovider >"$log" 2>&1
status=$?
grep -E "^(FAILED|ERROR) " "$log" || true
# the counts, reworded so that nothing reads this line as the locked run's verdict
summary="$(tail -n 1 "$log" | sed -E 's/=+//g; s/^ +| +$//g')"
echo "latest versions: pytest exit status $status (${summary})"
exit "$status"
