#!/usr/bin/env bash
# Measures what the guide's performance page (docs/performance.md) reports, on the machine's GPU, and
# writes the tables: nature and helicopter at 1920x1080 (the scenes' own MSAA, then MSAA
# off), the light's cost, the prairie flight, and a sweep to 10,000,000 blades.
#
#   scripts/gpu-measure.sh [OUT_DIR]      (default: gpu-figures/)
#
# OUT_DIR gets every bench's JSON report and tables.md (docs/performance.md's tables, Markdown).
# Needs only cargo and a GPU driver; CI never runs it. SWARD_ADAPTER picks the adapter
# (default: auto, the hardware one). FRAMES / WARMUP override the frame counts.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-gpu-figures}"
mkdir -p "$out"
frames="${FRAMES:-60}"
warmup="${WARMUP:-10}"
export SWARD_ADAPTER="${SWARD_ADAPTER:-auto}"

cargo build --release --bin sward --example gpu_tables
sward=target/release/sward
bench() { # NAME ARGS...: one bench run, its JSON kept as OUT/NAME.json
    local name=$1
    shift
    echo "== $name: sward bench $*" >&2
    "$sward" bench --json --frames "$frames" --warmup "$warmup" "$@" >"$out/$name.json"
}

bench nature --scene assets/scenes/nature.ron --size 1920x1080
bench nature-msaa-off --scene assets/scenes/nature.ron --size 1920x1080 --set render.msaa=1
bench helicopter --scene assets/scenes/helicopter.ron --size 1920x1080
bench helicopter-msaa-off --scene assets/scenes/helicopter.ron --size 1920x1080 --set render.msaa=1
bench nature-light --scene assets/scenes/nature.ron --size 1920x1080 --set render.msaa=1 --light
bench prairie-flight --scene assets/scenes/prairie.ron --size 1920x1080 --flight
bench sweep --scene assets/scenes/nature.ron --size 1920x1080 --set render.msaa=1 \
    --frames 10 --warmup 3 --sweep 100000,500000,1000000,2000000,5000000,10000000

target/release/examples/gpu_tables \
    "nature, 1920x1080, the scene's MSAA=$out/nature.json" \
    "nature, 1920x1080, MSAA off=$out/nature-msaa-off.json" \
    "helicopter, 1920x1080, the scene's MSAA=$out/helicopter.json" \
    "helicopter, 1920x1080, MSAA off=$out/helicopter-msaa-off.json" \
    "the light's cost, nature, 1920x1080, MSAA off=$out/nature-light.json" \
    "prairie flight, 1920x1080=$out/prairie-flight.json" \
    "sweep to 10,000,000 blades, nature, 1920x1080, MSAA off=$out/sweep.json" \
    >"$out/tables.md"
echo "wrote $out/tables.md: paste it under docs/performance.md's 'Measured' section" >&2
