//! The tunable numbers of the smooth formulation, with their defaults.

use crate::spec::model::Project;

/// Sharpness of the smooth functions and limits of the design, fixed for one optimization.
#[derive(Debug, Clone, PartialEq)]
pub struct Parameters {
    /// γ of eq. 21, dimensionless: the sigmoid `κ = 1 / (1 + e^(−γz))` that moves a ball between
    /// the ends of its capsule, where `z` is the cosine of the angle between the axis and gravity
    /// (the sine of the axis's elevation). Default 200: at the 3° minimum elevation of eq. 22
    /// (`z ≈ 0.052`) the ball is within 3·10⁻⁵ of its capsule's length from the end.
    pub ball_sharpness: f64,
    /// α of eq. 6, per radian: the smooth maximum over every goal of every pose. Default 100.
    pub goal_sharpness: f64,
    /// β of eq. 1, per radian: the smooth minimum over the toppling angles of one support.
    /// Default 100.
    pub edge_sharpness: f64,
    /// Points sampled along each capsule axis (both ends included) for the interior constraints
    /// of eq. 15; at least 2. Default 8 (the paper uses 32, fewer with many capsules).
    pub axis_samples: usize,
    /// The smallest printable capsule radius, project units. Default: the ball clearance plus
    /// 1 mm, so every capsule holds a ball at least 1 mm in radius.
    pub min_radius: f64,
    /// The length that rounds off the angle cones of eq. 2 and 4 and the point and segment
    /// supports of eq. 1, as a fraction of the model's extent (bounding-box diagonal of the
    /// posed vertices). Default 10⁻⁶.
    pub angle_smoothing: f64,
}

impl Parameters {
    /// The defaults for `project`.
    pub fn for_project(project: &Project) -> Parameters {
        Parameters {
            ball_sharpness: 200.0,
            goal_sharpness: 100.0,
            edge_sharpness: 100.0,
            axis_samples: 8,
            min_radius: project.ball.clearance + project.units.from_millimetres(1.0),
            angle_smoothing: 1e-6,
        }
    }

    /// The sample positions along an axis, `t ∈ [0, 1]` from `p` to `q`.
    pub(crate) fn samples(&self) -> Vec<f64> {
        let n = self.axis_samples.max(2);
        (0..n).map(|k| k as f64 / (n - 1) as f64).collect()
    }
}
