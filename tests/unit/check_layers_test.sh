#!/usr/bin/env bash
# The layer check passes on the tree as it is and refuses each kind of include against the arrows.
set -euo pipefail
checker=$1
source_root=$2
"$checker" "$source_root"

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
mkdir -p "$scratch"/{base,processing,render,ui,devices}
printf '#include "frame/frame.h"\n' >"$scratch/base/a.h"
printf '#include "processing/fog.h"\n#include "devices/session.h"\n' >"$scratch/processing/b.cpp"
printf '#include <imgui.h>\n' >"$scratch/render/c.cpp"
printf '#include <epoxy/gl.h>\n#include "devices/uvc/v4l2/v4l2_node.h"\n' >"$scratch/ui/d.cpp"
printf '#include "render/colormap.h"\n' >"$scratch/devices/e.cpp"
if "$checker" "$scratch" 2>"$scratch/out"; then
    echo "check-layers accepted includes against the arrows" >&2
    exit 1
fi
expected=(
    "base/a.h:1: base/ must not include <frame/frame.h>"
    "processing/b.cpp:2: processing/ must not include <devices/session.h>"
    "render/c.cpp:1: render/ must not include <imgui.h>"
    "ui/d.cpp:1: ui/ must not include <epoxy/gl.h>"
    "ui/d.cpp:2: ui/ must not include <devices/uvc/v4l2/v4l2_node.h>"
    "devices/e.cpp:1: devices/ must not include <render/colormap.h>"
)
for line in "${expected[@]}"; do
    grep -qxF "$line" "$scratch/out" || { echo "missing: $line" >&2; cat "$scratch/out" >&2; exit 1; }
done
if grep -q "processing/b.cpp:1:" "$scratch/out"; then
    echo "a layer's own include was refused" >&2
    exit 1
fi
echo "check-layers: $(grep -c 'must not include' "$scratch/out") planted violations refused, the tree passes"
