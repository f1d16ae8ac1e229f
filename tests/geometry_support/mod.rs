//! Meshes with known closed-form properties, and access to the shared real-mesh folder.
#![allow(dead_code)]

use std::collections::HashMap;
use std::path::PathBuf;

use ballast::geometry::TriMesh;
use nalgebra::Point3;

/// `mesh` as the text of an OBJ file (vertices, then triangles, indices from 1).
pub fn obj_text(mesh: &TriMesh) -> String {
    let mut text = String::new();
    for p in &mesh.positions {
        text.push_str(&format!("v {} {} {}\n", p.x, p.y, p.z));
    }
    for [a, b, c] in &mesh.triangles {
        text.push_str(&format!("f {} {} {}\n", a + 1, b + 1, c + 1));
    }
    text
}

/// The box [0,a]×[0,b]×[0,c]: 8 vertices (index = x + 2y + 4z), 12 triangles, outward.
pub fn box_mesh(a: f64, b: f64, c: f64) -> TriMesh {
    let positions = (0..8)
        .map(|i| {
            Point3::new(
                a * f64::from(i & 1),
                b * f64::from((i >> 1) & 1),
                c * f64::from((i >> 2) & 1),
            )
        })
        .collect();
    let triangles = vec![
        [0, 2, 1],
        [1, 2, 3], // z = 0
        [4, 5, 6],
        [5, 7, 6], // z = c
        [0, 1, 4],
        [1, 5, 4], // y = 0
        [2, 6, 3],
        [3, 6, 7], // y = b
        [0, 4, 2],
        [2, 4, 6], // x = 0
        [1, 3, 5],
        [3, 7, 5], // x = a
    ];
    TriMesh {
        positions,
        triangles,
    }
}

/// The unit cube [0,1]³.
pub fn unit_cube() -> TriMesh {
    box_mesh(1.0, 1.0, 1.0)
}

/// A right prism over the regular n-gon of circumradius `r` in the plane z = 0, height `h`.
/// Its volume is n/2 · r² · sin(2π/n) · h exactly.
pub fn prism(n: u32, r: f64, h: f64) -> TriMesh {
    let mut positions = Vec::new();
    for z in [0.0, h] {
        for i in 0..n {
            let t = 2.0 * std::f64::consts::PI * f64::from(i) / f64::from(n);
            positions.push(Point3::new(r * t.cos(), r * t.sin(), z));
        }
    }
    let mut triangles = Vec::new();
    for i in 1..n - 1 {
        triangles.push([0, i + 1, i]); // bottom, facing −z
        triangles.push([n, n + i, n + i + 1]); // top, facing +z
    }
    for i in 0..n {
        let j = (i + 1) % n;
        triangles.push([i, j, n + j]);
        triangles.push([i, n + j, n + i]);
    }
    TriMesh {
        positions,
        triangles,
    }
}

/// An icosahedron subdivided `levels` times, vertices on the sphere of radius `r` about `centre`.
pub fn icosphere(levels: u32, r: f64, centre: Point3<f64>) -> TriMesh {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut dirs: Vec<nalgebra::Vector3<f64>> = [
        [-1.0, g, 0.0],
        [1.0, g, 0.0],
        [-1.0, -g, 0.0],
        [1.0, -g, 0.0],
        [0.0, -1.0, g],
        [0.0, 1.0, g],
        [0.0, -1.0, -g],
        [0.0, 1.0, -g],
        [g, 0.0, -1.0],
        [g, 0.0, 1.0],
        [-g, 0.0, -1.0],
        [-g, 0.0, 1.0],
    ]
    .iter()
    .map(|v| nalgebra::Vector3::from(*v).normalize())
    .collect();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut mid = |a: u32, b: u32, dirs: &mut Vec<nalgebra::Vector3<f64>>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                dirs.push((dirs[a as usize] + dirs[b as usize]).normalize());
                (dirs.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(triangles.len() * 4);
        for [a, b, c] in triangles {
            let ab = mid(a, b, &mut dirs);
            let bc = mid(b, c, &mut dirs);
            let ca = mid(c, a, &mut dirs);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = next;
    }
    TriMesh {
        positions: dirs.iter().map(|d| centre + d * r).collect(),
        triangles,
    }
}

/// A path in the shared real-mesh folder (`../shared/meshes` beside the checkout), or `None`
/// (with a note on stderr) when the folder is not there.
pub fn shared_mesh(relative: &str) -> Option<PathBuf> {
    let folder = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/meshes");
    if !folder.is_dir() {
        eprintln!(
            "note: {} is missing; skipping the test on {relative}",
            folder.display()
        );
        return None;
    }
    Some(folder.join(relative))
}

/// A fixture in tests/data/meshes.
pub fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/meshes")
        .join(name)
}
