#!/usr/bin/env bash
# Compare two sward builds pass by pass on a noisy machine: run A, then B, N times
# alternating, each `sward render ARGS --trace` (the median of each pass over the frames
# after the third), and print per pass the medians of A and B and the geometric mean of
# the N paired ratios B/A with each ratio. On a shared 2-core machine one run against
# another drifts by 10-20 %; pairs taken back to back share the drift, so the mean of
# their ratios is good to a few per cent where single runs are not.
#
#   scripts/ab-passes.sh BIN_A BIN_B N RENDER_ARGS...
#   scripts/ab-passes.sh /tmp/sward-before target/release/sward 12 \
#       --scene assets/scenes/nature.ron --size 1280x720 --frames 8 --set render.msaa=1
#
# Needs python3. Build each binary first (copy the older one aside: a checkout and a
# rebuild replace target/release/sward).
set -euo pipefail
if [ $# -lt 4 ]; then
    sed -n '2,14p' "$0" >&2
    exit 2
fi
A=$1
B=$2
N=$3
shift 3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
    export XDG_RUNTIME_DIR="$work/xdg"
    mkdir -p "$XDG_RUNTIME_DIR"
    chmod 700 "$XDG_RUNTIME_DIR"
fi
for i in $(seq "$N"); do
    "$A" render "$@" --trace "$work/a$i.json" --out "$work/a.png" >/dev/null 2>&1
    "$B" render "$@" --trace "$work/b$i.json" --out "$work/b.png" >/dev/null 2>&1
done
python3 - "$work" "$N" <<'PY'
import json, math, statistics, sys

work, n = sys.argv[1], int(sys.argv[2])

def passes(path):
    events = [e for e in json.load(open(path))["traceEvents"] if e.get("ph") == "X"]
    by = {}
    for e in events:
        by.setdefault(e["name"], []).append(e["dur"] / 1000.0)
    frames = min(len(v) for v in by.values())
    by["frame"] = [sum(v[k] for v in by.values()) for k in range(frames)]
    return {name: statistics.median(v[3:] or v) for name, v in by.items()}

pairs = [(passes(f"{work}/a{i}.json"), passes(f"{work}/b{i}.json")) for i in range(1, n + 1)]
print(f"{'pass':14s} {'A ms':>8s} {'B ms':>8s}  B/A (geometric mean of {n} pairs), each pair")
for name in pairs[0][0]:
    a = [p[0].get(name, 0.0) for p in pairs]
    b = [p[1].get(name, 0.0) for p in pairs]
    if max(a) < 1.0:
        continue
    ratios = [y / x for x, y in zip(a, b) if x > 0 and y > 0]
    mean = math.exp(statistics.mean(math.log(r) for r in ratios))
    each = " ".join(f"{r:.2f}" for r in ratios)
    print(f"{name:14s} {statistics.median(a):8.1f} {statistics.median(b):8.1f}  x{mean:.3f}  {each}")
PY
