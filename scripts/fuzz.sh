#!/usr/bin/env bash
# Builds the `fuzz` preset (clang-14, libFuzzer, ASan, UBSan) and runs every fuzz target of fuzz/ in turn, one
# at a time, for SECONDS seconds each (docs/fuzzing.md).
#
#   scripts/fuzz.sh [SECONDS] [--merge] [--no-build] [--only NAME]...
#
#   SECONDS   per target, default 60.
#   --merge   afterwards, merge the new interesting inputs into fuzz/corpus/<target> (libFuzzer -merge=1: only
#             inputs that add coverage are kept).
#   --only    run only this target (fuzz_png, fuzz_obj, ...); may repeat.
#   --no-build  use build/fuzz as it is.
#
# The runs work in build/fuzz/runs/<target>/ (a copy of the seed corpus grows there; crashes are written there
# as crash-*, leak-*, timeout-*, oom-*). One line per target goes to build/fuzz/runs/summary.txt: seconds,
# executions, the oom-*, timeout-* and crash-*/leak-* files saved, exit status. Exit status: 0 when no
# target crashed, 1 otherwise. Memory: -rss_limit_mb=2048 and -malloc_limit_mb=1024 (a huge declared image or mesh
# size is refused by the readers' memory budget; see docs/fuzzing.md).
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=60
merge=0
build=1
only=()
while [[ $# -gt 0 ]]; do
    case "$1" in
        --merge) merge=1 ;;
        --no-build) build=0 ;;
        --only) only+=("$2"); shift ;;
        [0-9]*) seconds="$1" ;;
        *) echo "usage: scripts/fuzz.sh [SECONDS] [--merge] [--no-build] [--only NAME]..." >&2; exit 1 ;;
    esac
    shift
done

if [[ $build -eq 1 ]]; then
    if [[ -z "${CMAKE_CXX_COMPILER_LAUNCHER:-}" ]] && command -v ccache >/dev/null; then
        export CMAKE_CXX_COMPILER_LAUNCHER=ccache
    fi
    cmake --preset fuzz >/dev/null
    cmake --build --preset fuzz
fi

targets=()
if [[ ${#only[@]} -gt 0 ]]; then
    targets=("${only[@]}")
else
    for dir in fuzz/corpus/fuzz_*; do targets+=("$(basename "$dir")"); done
fi

runs=build/fuzz/runs
mkdir -p "$runs"
summary="$runs/summary.txt"
status=0
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
for target in "${targets[@]}"; do
    work="$runs/$target"
    mkdir -p "$work/corpus"
    cp -n fuzz/corpus/"$target"/* "$work/corpus/" 2>/dev/null || true
    log="$work/log.txt"
    set +e
    # Fork mode, one job at a time (-fork=1): an out-of-memory input (a huge declared size, which the readers'
    # memory budget refuses) or a timeout is saved as oom-* / timeout-* and the run goes on; a crash, a
    # sanitizer report or a leak stops it.
    (cd "$work" && "../../fuzz/$target" corpus -fork=1 -ignore_ooms=1 -ignore_timeouts=1 \
        -max_total_time="$seconds" -max_len=65536 -rss_limit_mb=2048 -malloc_limit_mb=1024 -timeout=10 \
        -print_final_stats=1) >"$log" 2>&1
    rc=$?
    set -e
    # The fork-mode stat lines: "#<executions so far>: cov: ... oom/timeout/crash: a/b/c time: <s>s job: ...".
    execs=$(grep -aoE '^#[0-9]+: cov' "$log" | tail -1 | grep -oE '[0-9]+' || echo 0)
    ooms=$(find "$work" -maxdepth 1 -name 'oom-*' | wc -l)
    timeouts=$(find "$work" -maxdepth 1 -name 'timeout-*' | wc -l)
    crashes=$(find "$work" -maxdepth 1 \( -name 'crash-*' -o -name 'leak-*' \) | wc -l)
    line="$target seconds=$seconds executions=${execs:-0} oom=$ooms timeout=$timeouts crash=$crashes rc=$rc"
    echo "$line" | tee -a "$summary"
    if [[ $rc -ne 0 || $crashes -ne 0 ]]; then
        status=1
        grep -aE 'ERROR|SUMMARY|Test unit written' "$log" | head -5 || true
    fi
    if [[ $merge -eq 1 ]]; then
        "build/fuzz/fuzz/$target" -merge=1 -max_len=65536 -rss_limit_mb=2048 -malloc_limit_mb=1024 \
            "fuzz/corpus/$target" "$work/corpus" >"$work/merge.txt" 2>&1 || true
    fi
done
exit $status
