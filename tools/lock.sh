#!/usr/bin/env bash
# Regenerate requirements/lock.txt, the pinned versions CI and the README's quick start install
# with (`pip install -c requirements/lock.txt ...`). pyproject.toml keeps the ranges a user's
# resolver sees; this file pins one resolution of them, for every extra, on every platform and
# Python the project supports (uv's universal resolution), so a release upstream cannot change
# what CI tests. Run it after changing a dependency range, or to move the lock forward once
# tools/check_latest.sh passes:
#
#     bash tools/lock.sh           # rewrite requirements/lock.txt
#     bash tools/lock.sh --check   # exit 1 if the lock does not resolve pyproject.toml's ranges
#
# uv is installed into a throw-away virtual environment; nothing else is touched.
set -euo pipefail
cd "$(dirname "$0")/.."
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
python3 -m venv "$tmp/venv"
"$tmp/venv/bin/pip" install -q uv 2>/dev/null
compile=("$tmp/venv/bin/uv" pip compile pyproject.toml --all-extras --universal
         --python-version 3.10 --no-header --annotation-style line --quiet)
if [ "${1:-}" = "--check" ]; then
  # the committed pins as preferences: a lock that still satisfies every range is unchanged
  cp requirements/lock.txt "$tmp/lock.txt"
  "${compile[@]}" -o "$tmp/lock.txt"
  if ! diff -u requirements/lock.txt "$tmp/lock.txt"; then
    echo "requirements/lock.txt is stale: run bash tools/lock.sh" >&2
    exit 1
  fi
  echo "requirements/lock.txt resolves pyproject.toml"
else
  "${compile[@]}" --upgrade -o requirements/lock.txt
  echo "wrote requirements/lock.txt ($(grep -c '==' requirements/lock.txt) pins)"
fi
