//! The print mass model against closed forms: the solid shell of a box, and the solid shell a
//! capsule adds (a ring between the capsule and the capsule dilated by the shell thickness).

mod balance_support;
mod geometry_support;

use std::f64::consts::PI;

use balance_support::*;
use ballast::balance::capsule_shell;
use ballast::geometry::{print_volumes, print_volumes_with_voids, Slicing, Void};
use ballast::spec::model::{Print, Units};
use geometry_support::box_mesh;
use nalgebra::{Point3, Rotation3, Vector3};

/// Slicing with `perimeter` thickness, layers of `h` (the first too), `n` top and bottom layers,
/// no small-region rule and no surface margin.
fn slicing(perimeter: f64, h: f64, n: usize) -> Slicing {
    Slicing {
        to_print: Rotation3::identity(),
        perimeter_thickness: perimeter,
        layer_height: h,
        first_layer_height: h,
        top_layers: n,
        bottom_layers: n,
        min_sparse_area: 0.0,
        surface_margin: 0.0,
        shell_widening: 0.0,
        fill_boundary: 0.0,
        infill_spacing: 0.0,
    }
}

#[test]
fn a_box_has_perimeter_walls_and_solid_top_and_bottom_layers() {
    // 40 × 30 × 20 in 80 layers of 0.25; walls 1.2 thick, 4 layers top and bottom.
    let (a, b, c) = (40.0, 30.0, 20.0);
    let (t, h, n) = (1.2, 0.25, 4);
    let volumes = print_volumes(&box_mesh(a, b, c), &slicing(t, h, n));
    let caps = 2.0 * n as f64 * h;
    let sparse = (a - 2.0 * t) * (b - 2.0 * t) * (c - caps);
    let solid = a * b * c - sparse;
    // The raster's cells are a quarter of the wall thick (0.3): each outline is right to within
    // a cell, 1 % of the sparse part's 37.6 × 27.6 footprint.
    assert_close("sparse", volumes.sparse.volume, sparse, 0.015 * sparse);
    assert_close("solid", volumes.solid.volume, solid, 0.015 * solid);
    for (what, region) in [("solid", volumes.solid), ("sparse", volumes.sparse)] {
        assert_point(
            &format!("{what} centroid"),
            region.centroid.coords.into(),
            [a / 2.0, b / 2.0, c / 2.0],
            0.02,
        );
    }
}

#[test]
fn an_off_centre_box_keeps_its_solid_and_sparse_centroids() {
    // The bottom layers are solid, so a box with more bottom than top layers has its solid part
    // lower than its middle: bottom 6 layers, top 2, no walls.
    let (a, b, c) = (20.0, 20.0, 10.0);
    let mut s = slicing(0.0, 0.5, 0);
    s.bottom_layers = 6;
    s.top_layers = 2;
    let volumes = print_volumes(&box_mesh(a, b, c), &s);
    // Layers of 0.5: the bottom 6 are z in [0, 3], the top 2 z in [9, 10].
    let solid_centre = (3.0 * 1.5 + 1.0 * 9.5) / 4.0;
    let solid = volumes.solid.volume;
    assert_close("solid", solid, a * b * 4.0, 0.005 * solid);
    assert_close("sparse", volumes.sparse.volume, a * b * 6.0, 0.005 * solid);
    assert_close("solid z", volumes.solid.centroid.z, solid_centre, 1e-9);
    assert_close("sparse z", volumes.sparse.centroid.z, 6.0, 1e-9);
}

/// The volume between a capsule (`p`, `q`, `r`) and its dilation by `t`, integrated on a grid
/// of `cell`: the points whose distance to the axis lies in (r, r + t].
fn ring_by_quadrature(p: Point3<f64>, q: Point3<f64>, r: f64, t: f64, cell: f64) -> f64 {
    let reach = r + t;
    let low = p.inf(&q) - Vector3::repeat(reach);
    let high = p.sup(&q) + Vector3::repeat(reach);
    let n = ((high - low) / cell).map(|x| x.ceil() as usize);
    let axis = q - p;
    let mut count = 0usize;
    for i in 0..n.x {
        for j in 0..n.y {
            for k in 0..n.z {
                let x = low + Vector3::new(i as f64 + 0.5, j as f64 + 0.5, k as f64 + 0.5) * cell;
                let s = ((x - p).dot(&axis) / axis.norm_squared()).clamp(0.0, 1.0);
                let d = (x - (p + axis * s)).norm();
                if d > r && d <= reach {
                    count += 1;
                }
            }
        }
    }
    count as f64 * cell.powi(3)
}

#[test]
fn a_capsule_adds_its_shell_solid_and_removes_the_sparse_infill_it_displaces() {
    // A tilted capsule in the middle of a 100 × 60 × 100 box, at infill 0.2, fdm defaults.
    let mut project = project(&["box"]);
    project.print = Print::defaults(Units::Millimetre);
    let t = capsule_shell(&project.print);
    let (p, q, r) = (
        Point3::new(30.0, 30.0, 40.0),
        Point3::new(70.0, 28.0, 55.0),
        6.0,
    );
    let mesh = box_mesh(100.0, 60.0, 100.0);
    let evaluate_with = |capsules| {
        let mut d = design(capsules);
        d.infill = 0.2;
        evaluate(
            &project,
            std::slice::from_ref(&mesh),
            &d,
            &rest_pose(1, vec![]),
        )
    };
    let plain = evaluate_with(vec![]);
    let holed = evaluate_with(vec![capsule(0, p, q, r, 0.0)]);
    let ring = ring_by_quadrature(p, q, r, t, 0.1);
    let length = (q - p).norm();
    let void = PI * r * r * (length + 4.0 / 3.0 * r);
    // Ring solid, sparse infill of ring and void removed, PLA in g/mm³.
    let change = (ring - 0.2 * (ring + void)) * PLA / 1000.0;
    assert_close(
        "mass change",
        holed.mass - plain.mass,
        change,
        2e-3 * change.abs(),
    );
    // The change sits on the axis midpoint: the centre of mass moves towards it.
    let middle = nalgebra::center(&p, &q);
    for axis in 0..3 {
        let expected = (plain.mass * plain.centre_of_mass[axis] + change * middle[axis])
            / (plain.mass + change);
        assert_close("centre", holed.centre_of_mass[axis], expected, 1e-3);
    }
    // The uniform model has no shell: the capsule only removes its void at the infill fraction.
    project.print.model = ballast::spec::model::MassModel::Uniform;
    assert_eq!(capsule_shell(&project.print), 0.0);
}

#[test]
fn odd_input_gives_empty_regions_not_a_panic() {
    let s = slicing(1.2, 0.3, 3);
    let empty = ballast::geometry::TriMesh {
        positions: vec![],
        triangles: vec![],
    };
    let mut broken = box_mesh(10.0, 10.0, 10.0);
    broken.positions[3].x = f64::NAN;
    let mut infinite = box_mesh(10.0, 10.0, 10.0);
    infinite.positions[5].y = f64::INFINITY;
    let mut out_of_range = box_mesh(10.0, 10.0, 10.0);
    out_of_range.triangles[0] = [0, 1, 99];
    for mesh in [&empty, &broken, &infinite] {
        let volumes = print_volumes(mesh, &s);
        assert_eq!(volumes.solid.volume + volumes.sparse.volume, 0.0);
    }
    // A triangle past the positions is skipped; the rest still slices.
    let volumes = print_volumes(&out_of_range, &s);
    assert!(volumes.solid.volume.is_finite() && volumes.sparse.volume.is_finite());
    let mut flat = s;
    flat.layer_height = 0.0;
    let volumes = print_volumes(&box_mesh(10.0, 10.0, 10.0), &flat);
    assert_eq!(volumes.solid.volume + volumes.sparse.volume, 0.0);
}

#[test]
fn a_void_cut_before_slicing_gets_a_ring_of_perimeters_and_solid_layers_over_and_under_it() {
    // A 30 × 30 × 40 box, a void along z through its middle (radius 5, axis from z = 12 to 28),
    // layers of 0.25, walls 1.2, 4 top and bottom layers, no margin or small-region rule.
    // Every layer the void crosses gets a ring of wall around its hole; the 4 layers under its
    // floor and over its ceiling are solid across the hole's widest slice in each of them.
    let (a, c) = (30.0, 40.0);
    let (t, h, n) = (1.2, 0.25, 4);
    let (r, low, high) = (5.0, 12.0, 28.0);
    let mesh = box_mesh(a, a, c);
    let s = slicing(t, h, n);
    let void = Void {
        from: Point3::new(a / 2.0, a / 2.0, low),
        to: Point3::new(a / 2.0, a / 2.0, high),
        radius: r,
    };
    let bare = print_volumes(&mesh, &s);
    let cut = print_volumes_with_voids(&mesh, &s, &[void]);
    // The void's volume leaves the part.
    let void_volume = PI * r * r * (high - low + 4.0 / 3.0 * r);
    let total = |v: &ballast::geometry::PrintVolumes| v.solid.volume + v.sparse.volume;
    assert_close(
        "void",
        total(&bare) - total(&cut),
        void_volume,
        0.02 * void_volume,
    );
    // The solid it adds: the ring along the axis, at least, and at most the ring over the whole
    // height of the void plus a disc of the ring's outer radius under and over it, n layers thick.
    let ring = PI * ((r + t).powi(2) - r * r);
    let added = cut.solid.volume - bare.solid.volume;
    let least = ring * (high - low);
    let most = ring * (high - low + 2.0 * r) + 2.0 * PI * (r + t).powi(2) * n as f64 * h;
    assert!(
        added > 0.97 * least && added < most,
        "solid added {added:.1}, between {least:.1} and {most:.1}"
    );
    // Symmetric about the box's middle: the centroids stay there.
    for (what, region) in [("solid", cut.solid), ("sparse", cut.sparse)] {
        assert_point(
            &format!("{what} centroid"),
            region.centroid.coords.into(),
            [a / 2.0, a / 2.0, c / 2.0],
            0.05,
        );
    }
}

#[test]
fn perimeters_or_solid_layers_thicker_than_the_part_print_it_solid_and_no_more() {
    // A long thin bar, about the T's 130 × 20 × 40: with 100 perimeters of 0.45 mm, or a
    // billion solid layers, every cell is solid and the material is the bar's volume.
    let bar = box_mesh(131.3, 20.7, 40.1);
    let volume = 131.3 * 20.7 * 40.1;
    for s in [slicing(45.0, 0.25, 3), slicing(1.35, 0.25, 1_000_000_000)] {
        let volumes = print_volumes(&bar, &s);
        assert!(volumes.sparse.volume.abs() < 1e-9 * volume, "{volumes:?}");
        let error = (volumes.solid.volume - volume).abs() / volume;
        // The raster rounds each side to whole cells: up to half a 0.34 mm cell on either side
        // of the 20.7 mm width is 1.6 %. (Before the cell followed the part's width, 100
        // perimeters made 11 mm cells: 11.5 % too much.)
        assert!(error < 0.02, "{volumes:?} against {volume}");
    }
}

#[test]
fn a_part_flat_in_one_direction_gets_a_bounded_raster() {
    // 100 mm long, a nanometre wide: the cell may not follow the width down (the raster would
    // need 10¹⁴ cells along the length), nor the overlap's measure of it.
    let flat = box_mesh(100.0, 1e-9, 10.0);
    let volumes = print_volumes(&flat, &slicing(1.35, 0.3, 3));
    assert!(volumes.solid.volume.is_finite() && volumes.sparse.volume.is_finite());
    // At most one row of cells 100 mm / 4096 wide: the raster's resolution, not the part's.
    let one_row = 100.0 / 4096.0 * 100.0 * 10.0;
    assert!(
        volumes.solid.volume + volumes.sparse.volume <= one_row * 1.01,
        "{volumes:?}"
    );
    let overlap = ballast::geometry::overlap(&flat);
    assert!(overlap.is_none_or(|o| o.volume.is_finite()));
}
