#!/bin/sh
# The long run of the kernels' numerical fuzz (tests/render/kernel_fuzz.rs): CASES random scenes
# (default 10000) on the GPU and the CPU twin, from SEED (default 22). Prints the test's
# summary line: cases sane on both backends, how many were well-conditioned and agreed.
#
#     scripts/kernel-fuzz.sh [CASES] [SEED]
set -eu
cd "$(dirname "$0")/.."
QJULIA_FUZZ_CASES="${1:-10000}" QJULIA_FUZZ_SEED="${2:-22}" \
    cargo test --release --test render kernel_fuzz:: -- --nocapture 2>&1 | grep -E "kernel fuzz|test result|panicked|failed"
