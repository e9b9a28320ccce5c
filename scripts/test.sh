#!/usr/bin/env bash
# Builds Strata (warnings are errors) and runs the whole test suite with ctest.
#   scripts/test.sh          the `ci` preset: release with -Werror
#   scripts/test.sh --asan   the `asan` preset: the same suite in a Debug build under AddressSanitizer and
#                            UBSan (docs/fuzzing.md#sanitizers-the-asan-preset)
set -euo pipefail
cd "$(dirname "$0")/.."
case "${1:-}" in
  "") preset=ci ;;
  --asan) preset=asan ;;
  *) echo "usage: scripts/test.sh [--asan]" >&2; exit 1 ;;
esac
scripts/build.sh "$preset"
ctest --preset "$preset"
