#!/usr/bin/env bash
# Measures what the guide's performance page (docs/performance.md) reports, on the machine's GPU, and
# writes the tables: nature and helicopter in the paper's setup (1024x768, 8x MSAA) beside
# the paper's own tables, and at 1920x1080 (the scenes' own MSAA, then MSAA off), the
# light's cost, the prairie flight, a sweep to 10,000,000 blades, the default meadow at
# 1280x720 and the peer's scene from 8,192 to 524,288 blades. With nvidia-smi on the PATH
# the SM clock is logged beside them (OUT_DIR/clocks.csv): a GPU left idle lowers it.
#
#   scripts/gpu-measure.sh [OUT_DIR]      (default: gpu-figures/)
#
# OUT_DIR gets every bench's JSON report and tables.md (docs/performance.md's tables, Markdown).
# Needs only cargo and a GPU driver; CI never runs it. SWARD_ADAPTER picks the adapter
# (default: auto, the hardware one). FRAMES / WARMUP override the frame counts; SWEEP the
# sweep's blade counts (comma-separated), SWEEP_FRAMES / SWEEP_WARMUP its frame counts. On a
# machine without cargo, build here and point SWARD_BIN and GPU_TABLES at the built `sward`
# and `examples/gpu_tables`: nothing is built then.
#
# Vulkan needs the loader (libvulkan.so.1) and, for NVIDIA's ICD, libglvnd (libGLdispatch):
# without libglvnd the loader finds the ICD but not its vkCreateInstance and sward says
# "no GPU adapter found". On a headless NVIDIA machine, point VK_DRIVER_FILES at the
# driver's nvidia_icd.json (docs/performance.md, "Measured on a GPU", says what was needed).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-gpu-figures}"
mkdir -p "$out"
frames="${FRAMES:-60}"
warmup="${WARMUP:-10}"
export SWARD_ADAPTER="${SWARD_ADAPTER:-auto}"

sweep="${SWEEP:-100000,500000,1000000,2000000,5000000,10000000}"
sward="${SWARD_BIN:-target/release/sward}"
tables="${GPU_TABLES:-target/release/examples/gpu_tables}"
if [[ -z "${SWARD_BIN:-}" || -z "${GPU_TABLES:-}" ]]; then
    cargo build --release --bin sward --example gpu_tables
fi
"$sward" --version >&2 || true
bench() { # NAME ARGS...: one bench run, its JSON kept as OUT/NAME.json
    local name=$1
    shift
    echo "== $name: sward bench $*" >&2
    "$sward" bench --json "$@" >"$out/$name.json"
}

if command -v nvidia-smi >/dev/null; then
    nvidia-smi --query-gpu=timestamp,clocks.sm,utilization.gpu --format=csv -lms 500 \
        >"$out/clocks.csv" &
    trap 'kill $! 2>/dev/null' EXIT
fi

run="--frames $frames --warmup $warmup"
bench nature-paper $run --scene assets/scenes/nature.ron --size 1024x768 --set render.msaa=8
bench helicopter-paper $run --scene assets/scenes/helicopter.ron --size 1024x768 --set render.msaa=8
bench nature $run --scene assets/scenes/nature.ron --size 1920x1080
bench nature-msaa-off $run --scene assets/scenes/nature.ron --size 1920x1080 --set render.msaa=1
bench helicopter $run --scene assets/scenes/helicopter.ron --size 1920x1080
bench helicopter-msaa-off $run --scene assets/scenes/helicopter.ron --size 1920x1080 --set render.msaa=1
bench nature-light $run --scene assets/scenes/nature.ron --size 1920x1080 --set render.msaa=1 --light
bench prairie-flight $run --scene assets/scenes/prairie.ron --size 1920x1080 --flight
# The sweep's largest fields take a while to build: fewer frames. The GPU idles while each
# is built and its clock drops (345 MHz on the H200, against 1980 under load): 3 warm-up
# frames left the 1M and 2M points of one run at half speed (the fixed-size tone map 0.48
# and 0.61 ms against 0.34), so each point warms up for 30.
bench sweep --frames "${SWEEP_FRAMES:-10}" --warmup "${SWEEP_WARMUP:-30}" --scene assets/scenes/nature.ron \
    --size 1920x1080 --set render.msaa=1 --sweep "$sweep"
bench meadow $run --size 1280x720
bench peer $run --scene assets/scenes/peer.ron --size 1280x720 --set render.msaa=1 \
    --sweep 8192,32768,131072,524288

"$tables" \
    "paper:nature=$out/nature-paper.json" \
    "paper:helicopter=$out/helicopter-paper.json" \
    "nature, 1920x1080, the scene's MSAA=$out/nature.json" \
    "nature, 1920x1080, MSAA off=$out/nature-msaa-off.json" \
    "helicopter, 1920x1080, the scene's MSAA=$out/helicopter.json" \
    "helicopter, 1920x1080, MSAA off=$out/helicopter-msaa-off.json" \
    "the light's cost, nature, 1920x1080, MSAA off=$out/nature-light.json" \
    "prairie flight, 1920x1080=$out/prairie-flight.json" \
    "sweep to ${sweep##*,} blades, nature, 1920x1080, MSAA off=$out/sweep.json" \
    "the default meadow, 1280x720=$out/meadow.json" \
    "the peer's scene, 1280x720, MSAA off=$out/peer.json" \
    >"$out/tables.md"
echo "wrote $out/tables.md: paste it under docs/performance.md's 'Measured' section" >&2
