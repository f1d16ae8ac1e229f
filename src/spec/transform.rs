//! Transform blocks: the `pivot`, `rotate` and `translate` steps of a pose, or of a component
//! block inside a pose, composed into one rigid transform.
//!
//! # Semantics
//!
//! The steps apply in file order, starting from the identity. Every step acts in one fixed frame:
//! the frame the block starts from, which for both a pose and a component block is the rest frame
//! (the frame the meshes are written in). With `T` the transform so far:
//!
//! - `pivot x y z` sets the current pivot `p` (the origin until a `pivot` step) to a point of
//!   that fixed frame. It does not move anything, and it does not follow earlier steps.
//! - `rotate rx ry rz` rotates by extrinsic X, then Y, then Z Euler angles in degrees,
//!   `R = Rz·Ry·Rx`, about the current pivot: `T ← Tr(p)·R·Tr(−p)·T`.
//! - `translate x y z` moves by `v`: `T ← Tr(v)·T`.
//!
//! So `pivot 1 0 0; rotate 0 0 90` maps the point (2, 0, 0) to (1, 1, 0), and
//! `rotate 0 0 90; translate 1 0 0` (rotate, then move along the fixed x axis) differs from
//! `translate 1 0 0; rotate 0 0 90` (move, then rotate the moved model about the origin).

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};

/// One step of a transform block. Lengths are in project units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Step {
    /// Sets the point later rotations turn about.
    Pivot(Point3<f64>),
    /// Extrinsic X, Y, Z Euler angles in degrees.
    Rotate(Vector3<f64>),
    /// A displacement.
    Translate(Vector3<f64>),
}

/// The rotation `Rz·Ry·Rx` for extrinsic X, Y, Z Euler angles in degrees.
pub fn rotation(degrees: Vector3<f64>) -> UnitQuaternion<f64> {
    let radians = degrees.map(f64::to_radians);
    UnitQuaternion::from_axis_angle(&Vector3::z_axis(), radians.z)
        * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), radians.y)
        * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), radians.x)
}

/// Composes `steps` in order, starting from the identity (see the module documentation).
pub fn compose(steps: impl IntoIterator<Item = Step>) -> Isometry3<f64> {
    let mut pivot = Point3::origin();
    let mut transform = Isometry3::identity();
    for step in steps {
        match step {
            Step::Pivot(point) => pivot = point,
            Step::Rotate(degrees) => {
                let rotation = rotation(degrees);
                // Tr(p)·R·Tr(−p) is the rotation R followed by the translation p − R·p.
                let shift = pivot.coords - rotation * pivot.coords;
                transform = Isometry3::from_parts(Translation3::from(shift), rotation) * transform;
            }
            Step::Translate(displacement) => {
                transform = Translation3::from(displacement) * transform;
            }
        }
    }
    transform
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Point3<f64>, b: Point3<f64>) -> bool {
        (a - b).norm() < 1e-12
    }

    #[test]
    fn rotation_about_a_pivot() {
        let transform = compose([
            Step::Pivot(Point3::new(1.0, 0.0, 0.0)),
            Step::Rotate(Vector3::new(0.0, 0.0, 90.0)),
        ]);
        assert!(close(
            transform * Point3::new(2.0, 0.0, 0.0),
            Point3::new(1.0, 1.0, 0.0)
        ));
    }

    #[test]
    fn euler_angles_are_extrinsic_xyz() {
        // Rx(90) takes y to z; then Rz(90) takes z to z: (0,1,0) -> (0,0,1).
        let r = rotation(Vector3::new(90.0, 0.0, 90.0));
        assert!(close(
            r * Point3::new(0.0, 1.0, 0.0),
            Point3::new(0.0, 0.0, 1.0)
        ));
        // Rx(90) takes x to x; then Rz(90) takes x to y.
        assert!(close(
            r * Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0)
        ));
    }

    #[test]
    fn order_matters() {
        let quarter = Step::Rotate(Vector3::new(0.0, 0.0, 90.0));
        let shift = Step::Translate(Vector3::new(1.0, 0.0, 0.0));
        let origin = Point3::origin();
        assert!(close(
            compose([quarter, shift]) * origin,
            Point3::new(1.0, 0.0, 0.0)
        ));
        assert!(close(
            compose([shift, quarter]) * origin,
            Point3::new(0.0, 1.0, 0.0)
        ));
    }
}
