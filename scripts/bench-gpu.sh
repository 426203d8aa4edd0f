#!/usr/bin/env bash
# The benchmark on a machine with a real GPU: names the card, then runs `cargo bench` on Vulkan
# and keeps its summary (target/criterion/qjulia-summary.md) beside the log. Where the Vulkan
# loader is missing (a bare container), install libvulkan1 first.
set -euo pipefail
cd "$(dirname "$0")/.."
export WGPU_BACKEND="${WGPU_BACKEND:-vulkan}"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/xdg-runtime-$(id -u)}"
mkdir -p -m 700 "$XDG_RUNTIME_DIR" target
{
    echo "== $(date -u) on $(hostname)"
    command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader
    cargo run --release --quiet -- info
    cargo bench
} 2>&1 | tee target/bench-gpu.log
cp target/criterion/qjulia-summary.md target/bench-gpu-summary.md
echo "summary: target/bench-gpu-summary.md"
