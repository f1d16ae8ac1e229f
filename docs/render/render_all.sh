#!/bin/sh
# Builds every example (or the ones named: `render_all.sh t_shape spot`) with the release binary
# and renders one PNG per pose into docs/images/ with render_poses.py. See docs/render/README.md.
#
# The examples are built from a copy in a temporary folder, so the repository's solution files
# stay as they are. Environment: BALLAST (the binary, default target/release/ballast), BLENDER
# (default blender), ENGINE (eevee, the default, or cycles; when EEVEE fails, Cycles renders
# instead), OUT_DIR (default docs/images), BALLAST_CACHE_DIR (default /tmp/cache-render).
set -eu

repo=$(cd "$(dirname "$0")/../.." && pwd)
ballast=${BALLAST:-$repo/target/release/ballast}
blender=${BLENDER:-blender}
engine=${ENGINE:-eevee}
out=${OUT_DIR:-$repo/docs/images}
export BALLAST_CACHE_DIR="${BALLAST_CACHE_DIR:-/tmp/cache-render}"

if [ ! -x "$ballast" ]; then
    echo "render_all.sh: no ballast binary at $ballast (cargo build --release)" >&2
    exit 1
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
cp -R "$repo/examples" "$tmp/examples"
rm -rf "$tmp/examples/build"
mkdir -p "$out"

if [ $# -gt 0 ]; then
    names="$*"
else
    names=$(cd "$tmp/examples" && ls *.kdl | grep -v '\.solution\.kdl$' | sed 's/\.kdl$//')
fi

render() {
    "$blender" -b --factory-startup --python-exit-code 1 \
        --python "$repo/docs/render/render_poses.py" -- "$1" "$out" --engine "$2" \
        >"$tmp/blender.log" 2>&1
}

for name in $names; do
    project="$tmp/examples/$name.kdl"
    echo "== $name"
    "$ballast" build "$project" --out-dir "$tmp/build" >"$tmp/build.log" 2>&1 || {
        cat "$tmp/build.log" >&2
        echo "render_all.sh: building $name failed" >&2
        exit 1
    }
    glb="$tmp/build/$name.glb"
    if render "$glb" "$engine"; then
        :
    elif [ "$engine" != cycles ] && echo "render_all.sh: $engine failed, rendering $name with Cycles" >&2 \
        && render "$glb" cycles; then
        :
    else
        cat "$tmp/blender.log" >&2
        echo "render_all.sh: rendering $name failed" >&2
        exit 1
    fi
    grep '^render_poses: ' "$tmp/blender.log" | sed "s|$repo/||"
done
