#!/bin/sh
# Fuzzes the scene loader for a bounded time under ASan and UBSan
# (tests/fuzz/fuzz_scene_loader.c), seeded with the shipped scenes: builds
# the target with clang in its own folder, then runs it for SB_FUZZ_SECONDS
# (default 15). A crash, a leak, a sanitizer report or a timeout fails the
# test and leaves the input under <build>/fuzz/; inputs it once found are
# kept in tests/fuzz/regressions/ and replayed as seeds. Without clang (tools/setup
# installs it) there is nothing to run: the test says so and exits 77, which
# CTest reports as a skip (SKIP_RETURN_CODE), never as a pass.
# Usage: test_fuzz.sh <source root> <build dir>
set -u
root=$1 build=$2/fuzz
seconds=${SB_FUZZ_SECONDS:-15}
if ! command -v clang >/dev/null || ! command -v clang++ >/dev/null; then
    echo "skipped: no clang (tools/setup installs it)"
    exit 77
fi
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DSB_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null &&
    cmake --build "$build" --target fuzz_scene_loader -j "$(nproc)" >/dev/null || { echo "FAILED: build"; exit 1; }
corpus=$(mktemp -d)
trap 'rm -rf "$corpus"' EXIT
cp "$root"/scenes/*.gltf "$root"/tests/fuzz/regressions/* "$corpus"/  # what it found before, replayed first
cd "$build" || exit 1
./fuzz_scene_loader -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
    -print_final_stats=1 "$corpus" > fuzz.log 2>&1
rc=$?
tail -12 fuzz.log
[ $rc = 0 ] || echo "FAILED: the fuzzer found a crash, leak or hang (exit $rc): see $build/fuzz.log and the crash-* file there"
exit $rc
