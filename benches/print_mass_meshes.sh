#!/bin/bash
# The mass model against PrusaSlicer on meshes nobody tuned it for: each mesh is one component
# of a project without capsules, built by `ballast build` (its own print orientation, the
# default print settings), its PrusaSlicer project sliced by the installed `prusa-slicer`, and
# the plastic the G-code deposits compared with the model's by `ballast verify --gcode`. Prints
# one Markdown row per mesh: model, G-code, their difference, and how far apart the centres are.
#
#   benches/print_mass_meshes.sh [NAME=MESH:ATTRIBUTES ...]
#
# Without arguments it measures the meshes in the repository; each argument adds one, e.g.
#   torus=/path/to/torus.obj:scale=30
# Needs a release build (`cargo build --release`) and `prusa-slicer` on the PATH.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${BALLAST:-$root/target/release/ballast}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
meshes=(
    "hammer=$root/examples/meshes/hammer.obj:mesh-units=in"
    "spot=$root/examples/meshes/spot.obj:mesh-units=in"
    "fish=$root/examples/meshes/blub_fish.obj:mesh-units=in"
    "boat=$root/benches/projects/meshes/boat.obj:mesh-units=in scale=0.5"
)
for part in head pelvis l_thigh l_forearm l_foot; do
    meshes+=("poppy $part=$root/benches/projects/meshes/poppy_humanoid.obj:object=\"$part\" mesh-units=m")
done
if [ $# -gt 0 ]; then
    meshes+=("$@")
fi
echo "| mesh | model | G-code | mass | centres apart |"
echo "| --- | ---: | ---: | ---: | ---: |"
for entry in "${meshes[@]}"; do
    name=${entry%%=*}
    rest=${entry#*=}
    mesh=${rest%%:*}
    attributes=${rest#*:}
    project="$work/${name// /_}.kdl"
    cat > "$project" <<KDL
units mm
up z
material "PLA" density=1.24
ball density=7.85 clearance=0.2
infill 0.15
wall 1.2
component "part" mesh="$mesh" $attributes
pose "rest" {
    stand
}
KDL
    stem=$(basename "$project" .kdl)
    "$bin" build --read-outside "$project" > "$work/$stem.build.log" 2>&1
    prusa-slicer --export-gcode --dont-arrange "$work/build/$stem.3mf" -o "$work/$stem.gcode" \
        > "$work/$stem.slice.log" 2>&1
    "$bin" verify --read-outside "$project" --gcode "$work/$stem.gcode" --json \
        > "$work/$stem.json" 2> /dev/null || true
    python3 - "$name" "$work/$stem.json" <<'PY'
import json, math, sys
name, path = sys.argv[1], sys.argv[2]
pose = json.load(open(path))["poses"][0]
model, sliced = pose["computed_mass"], pose["sliced_mass"]
apart = math.dist(pose["computed_centre"], pose["sliced_centre"])
print(f"| {name} | {model:.2f} g | {sliced:.2f} g | {100 * (model - sliced) / sliced:+.2f} % | {apart:.2f} mm |")
PY
done
