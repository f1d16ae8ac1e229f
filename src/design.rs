//! A design: the capsules (and infill) chosen for a project, whether placed by hand or, later, by
//! the optimizer. The physics and fabrication stages evaluate a design; they do not care where it
//! came from.

use nalgebra::Point3;

/// The capsules and infill to evaluate.
#[derive(Debug, Clone, PartialEq)]
pub struct Design {
    /// The capsules, in a stable order (file order for hand-placed ones).
    pub capsules: Vec<PlacedCapsule>,
    /// Fraction of the printed interior that is filled, in (0, 1].
    pub infill: f64,
}

impl Design {
    /// The capsules held by component `component`, each with its index in `capsules`, in order.
    pub fn capsules_of(&self, component: usize) -> Vec<(usize, &PlacedCapsule)> {
        self.capsules
            .iter()
            .enumerate()
            .filter(|(_, capsule)| capsule.component == component)
            .collect()
    }
}

/// One capsule-shaped void and the ball inside it, in the rest frame of its component.
#[derive(Debug, Clone, PartialEq)]
pub struct PlacedCapsule {
    /// The capsule's name, for reports.
    pub name: String,
    /// Index of the component holding it.
    pub component: usize,
    /// One end of the axis, rest frame.
    pub from: Point3<f64>,
    /// The other end of the axis, rest frame.
    pub to: Point3<f64>,
    /// Radius of the void.
    pub radius: f64,
    /// Radius of the ball; smaller than `radius` by at least the ball clearance.
    pub ball_radius: f64,
}

impl PlacedCapsule {
    /// Length of the axis, `|to − from|`.
    pub fn axis_length(&self) -> f64 {
        (self.to - self.from).norm()
    }

    /// Volume of the void: a cylinder plus two hemispheres, `πr²|q−p| + 4/3 πr³`.
    pub fn volume(&self) -> f64 {
        let r = self.radius;
        std::f64::consts::PI * r * r * (self.axis_length() + 4.0 / 3.0 * r)
    }

    /// Volume of the ball, `4/3 πb³`.
    pub fn ball_volume(&self) -> f64 {
        4.0 / 3.0 * std::f64::consts::PI * self.ball_radius.powi(3)
    }
}
