#!/usr/bin/env python3
"""ballast's signed distance grid against libigl's signed distance on the same nodes, in one run.

Runs `cargo bench --bench precompute` with BALLAST_BENCH_EXPORT set (every mesh of that bench,
scaled as it is there, and its grid at the default spacing), then asks libigl's
`signed_distance` for the signed distance at exactly those grid nodes, signed by the fast
winding number (ballast signs by the winding number too) and by the pseudonormal (libigl's
default), and prints, per mesh, both times, their ratio, the largest difference of the unsigned
distances, and at how many nodes off the surface the signs differ. ballast's grid leaves the
blocks far outside out of its build (the "deferred" nodes, computed afterwards by a background
thread or when read); the export reads them all, so the distances compared are every node's.

Needs the `libigl` Python package (`pip install libigl`). Extra arguments are passed to the
environment filter of the bench: `benches/igl_compare.py hammer` keeps the meshes whose label
contains "hammer". Figures: docs/benchmarks.md, "Precompute against libigl".
"""

import json
import os
import pathlib
import re
import subprocess
import sys
import tempfile
import time

import igl
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent


def load_obj(path):
    """The vertices and triangles of an OBJ file as the bench wrote it (v and f lines only)."""
    vertices, faces = [], []
    with open(path) as lines:
        for line in lines:
            if line.startswith("v "):
                vertices.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                faces.append([int(x) - 1 for x in line.split()[1:4]])
    return np.array(vertices, dtype=np.float64), np.array(faces, dtype=np.int64)


def nodes(header):
    """Every grid node's position, x fastest, as the grid stores its values."""
    nx, ny, nz = header["dims"]
    k, j, i = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
    index = np.stack([i.ravel(), j.ravel(), k.ravel()], axis=1).astype(np.float64)
    return np.asarray(header["origin"]) + header["cell"] * index


def timed(function):
    start = time.perf_counter()
    result = function()
    return time.perf_counter() - start, result


def main():
    env = dict(os.environ)
    if len(sys.argv) > 1:
        env["BALLAST_BENCH_FILTER"] = sys.argv[1]
    with tempfile.TemporaryDirectory() as folder:
        env["BALLAST_BENCH_EXPORT"] = folder
        bench = subprocess.run(
            ["cargo", "bench", "--bench", "precompute"],
            cwd=ROOT,
            env=env,
            capture_output=True,
            text=True,
            check=True,
        )
        ours = {}
        for line in bench.stdout.splitlines():
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if len(cells) == 8 and re.fullmatch(r"[0-9.]+", cells[5]):
                ours[cells[0]] = (int(cells[1]), int(cells[3]), int(cells[4]), float(cells[5]))
        print("| mesh | triangles | nodes | deferred | ballast grid s | libigl fast winding s | "
              "ratio | libigl pseudonormal s | ratio | largest difference | signs apart |")
        print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
        for label, (triangles, count, deferred, grid_seconds) in ours.items():
            base = pathlib.Path(folder)
            vertices, faces = load_obj(base / f"{label}.obj")
            header = json.loads((base / f"{label}.grid.json").read_text())
            values = np.fromfile(base / f"{label}.grid.f64", dtype="<f8")
            points = nodes(header)
            assert len(points) == len(values) == count
            fast_seconds, (fast, _, _, _) = timed(lambda: igl.signed_distance(
                points, vertices, faces,
                sign_type=igl.SIGNED_DISTANCE_TYPE_FAST_WINDING_NUMBER))
            normal_seconds, (normal, _, _, _) = timed(lambda: igl.signed_distance(
                points, vertices, faces, sign_type=igl.SIGNED_DISTANCE_TYPE_PSEUDONORMAL))
            apart = np.abs(np.abs(values) - np.abs(normal)).max()
            # Nodes on the surface (distance 0) have no sign to compare.
            off = np.abs(values) > 1e-9 * header["cell"]
            signs = int(np.count_nonzero(np.sign(values[off]) != np.sign(fast[off])))
            print(f"| {label} | {triangles} | {count} | {deferred} | {grid_seconds:.3f} | "
                  f"{fast_seconds:.3f} | {fast_seconds / grid_seconds:.1f} | "
                  f"{normal_seconds:.3f} | {normal_seconds / grid_seconds:.1f} | "
                  f"{apart:.2e} | {signs} |")


if __name__ == "__main__":
    main()
