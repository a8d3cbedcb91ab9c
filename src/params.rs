//! Every tunable of the mesher in one place.
//!
//! [`Params`] is the single source of the parameter names: the CLI derives its
//! flags from it (`--angle-threshold`, …, through `clap::Args` behind the `cli`
//! feature) and the Python keyword arguments are the same names in snake case,
//! checked against [`PARAM_NAMES`] by a test, so the three cannot drift.

/// Default of [`Params::angle_threshold`] (degrees).
pub const DEFAULT_ANGLE_THRESHOLD: f64 = 10.0;
/// Default of [`Params::k1`].
pub const DEFAULT_K1: u32 = 1;
/// Default of [`Params::min_vertices`].
pub const DEFAULT_MIN_VERTICES: u32 = 12;
/// Default of [`Params::max_vertices`].
pub const DEFAULT_MAX_VERTICES: u32 = 64;
/// Default of [`Params::cap_rings`].
pub const DEFAULT_CAP_RINGS: u32 = 3;
/// Default of [`Params::resolution`].
pub const DEFAULT_RESOLUTION: f64 = 1.0;
/// Default of [`Params::min_radius`] (0 = automatic floor only).
pub const DEFAULT_MIN_RADIUS: f64 = 0.0;
/// Default of [`Params::scale`].
pub const DEFAULT_SCALE: f64 = 1.0;

/// The names of all parameters, as CLI flags (with `-` for `_`) and Python keywords.
pub const PARAM_NAMES: [&str; 8] = [
    "angle_threshold",
    "k1",
    "min_vertices",
    "max_vertices",
    "cap_rings",
    "resolution",
    "min_radius",
    "scale",
];

/// Tunables of the meshing pipeline, each with the paper formula it feeds.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct Params {
    /// Best-successor tie threshold t, in degrees (paper §3.1).
    ///
    /// When the two straightest children of a branch point deviate from the
    /// incoming direction by angles closer than this, the child whose radius is
    /// closest to the branch point's continues the branch. Default 10.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_ANGLE_THRESHOLD, help_heading = "Mesh parameters"))]
    pub angle_threshold: f64,
    /// Extra spline samples per segment, k1 of formula (1).
    ///
    /// Between two original points the resampler inserts
    /// floor(D / r_avg × resolution) + k1 samples; the first segment of a branch
    /// gets k1 + 1 (the paper's endpoint rule). Default 1.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_K1, help_heading = "Mesh parameters"))]
    pub k1: u32,
    /// Fewest vertices on a contour (even, formula 3's floor).
    ///
    /// Formula (3) gives few vertices where the radius is near the branch average;
    /// this floor keeps thin tubes round (12 keeps a tube's area and volume within 1 % of the round tube's). Default 12.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_MIN_VERTICES, help_heading = "Mesh parameters"))]
    pub min_vertices: u32,
    /// Most vertices on a contour (even, formula 3's cap).
    ///
    /// Caps the count where a thick point sits on a thin branch. Default 64.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_MAX_VERTICES, help_heading = "Mesh parameters"))]
    pub max_vertices: u32,
    /// Shrinking rings in each tip cap before its apex.
    ///
    /// Tips are closed by a dome inside the last sample's sphere; more rings make
    /// it rounder. 0 closes a tip with a flat fan. Default 3.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_CAP_RINGS, help_heading = "Mesh parameters"))]
    pub cap_rings: u32,
    /// Global resolution factor (edge length = r_avg / resolution).
    ///
    /// Multiplies the sampling density along branches (formula 1) and around
    /// contours (formula 3). 2 gives about four times the triangles. Default 1.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_RESOLUTION, help_heading = "Mesh parameters"))]
    pub resolution: f64,
    /// Smallest radius used, in output units (0 = automatic).
    ///
    /// Radii below it are raised to it. Whatever its value, radii are never
    /// below 1e-5 × the largest coordinate (measured from the point a cell
    /// far from the origin is built around), so f32 output keeps contours
    /// distinct.
    /// Default 0.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_MIN_RADIUS, help_heading = "Mesh parameters"))]
    pub min_radius: f64,
    /// Factor applied to coordinates and radii (unit conversion).
    ///
    /// For example 0.001 turns nanometres into micrometres, 0.008 turns 8 nm
    /// voxels into micrometres. Default 1.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_SCALE, help_heading = "Mesh parameters"))]
    pub scale: f64,
}

impl Default for Params {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl Params {
    /// All defaults.
    pub const DEFAULT: Params = Params {
        angle_threshold: DEFAULT_ANGLE_THRESHOLD,
        k1: DEFAULT_K1,
        min_vertices: DEFAULT_MIN_VERTICES,
        max_vertices: DEFAULT_MAX_VERTICES,
        cap_rings: DEFAULT_CAP_RINGS,
        resolution: DEFAULT_RESOLUTION,
        min_radius: DEFAULT_MIN_RADIUS,
        scale: DEFAULT_SCALE,
    };

    /// Sets [`Params::angle_threshold`].
    pub const fn with_angle_threshold(mut self, degrees: f64) -> Self {
        self.angle_threshold = degrees;
        self
    }
    /// Sets [`Params::k1`].
    pub const fn with_k1(mut self, k1: u32) -> Self {
        self.k1 = k1;
        self
    }
    /// Sets [`Params::min_vertices`].
    pub const fn with_min_vertices(mut self, n: u32) -> Self {
        self.min_vertices = n;
        self
    }
    /// Sets [`Params::max_vertices`].
    pub const fn with_max_vertices(mut self, n: u32) -> Self {
        self.max_vertices = n;
        self
    }
    /// Sets [`Params::cap_rings`].
    pub const fn with_cap_rings(mut self, n: u32) -> Self {
        self.cap_rings = n;
        self
    }
    /// Sets [`Params::resolution`].
    pub const fn with_resolution(mut self, factor: f64) -> Self {
        self.resolution = factor;
        self
    }
    /// Sets [`Params::min_radius`].
    pub const fn with_min_radius(mut self, r: f64) -> Self {
        self.min_radius = r;
        self
    }
    /// Sets [`Params::scale`].
    pub const fn with_scale(mut self, factor: f64) -> Self {
        self.scale = factor;
        self
    }

    /// Checks every value against its valid range.
    ///
    /// # Errors
    /// [`crate::Error::InvalidParam`] naming the first bad parameter.
    pub fn validate(&self) -> crate::Result<()> {
        let bad =
            |name: &'static str, reason: String| Err(crate::Error::InvalidParam { name, reason });
        if !(self.angle_threshold.is_finite() && (0.0..=180.0).contains(&self.angle_threshold)) {
            return bad(
                "angle_threshold",
                format!("must be in [0, 180] degrees, got {}", self.angle_threshold),
            );
        }
        if self.k1 > 64 {
            return bad("k1", format!("must be at most 64, got {}", self.k1));
        }
        if !(4..=1024).contains(&self.min_vertices) || !self.min_vertices.is_multiple_of(2) {
            return bad(
                "min_vertices",
                format!("must be even and in [4, 1024], got {}", self.min_vertices),
            );
        }
        if !(4..=1024).contains(&self.max_vertices) || !self.max_vertices.is_multiple_of(2) {
            return bad(
                "max_vertices",
                format!("must be even and in [4, 1024], got {}", self.max_vertices),
            );
        }
        if self.max_vertices < self.min_vertices {
            return bad(
                "max_vertices",
                format!(
                    "must be at least min_vertices ({}), got {}",
                    self.min_vertices, self.max_vertices
                ),
            );
        }
        if self.cap_rings > 64 {
            return bad(
                "cap_rings",
                format!("must be at most 64, got {}", self.cap_rings),
            );
        }
        if !(self.resolution.is_finite() && self.resolution > 0.0 && self.resolution <= 16.0) {
            return bad(
                "resolution",
                format!("must be in (0, 16], got {}", self.resolution),
            );
        }
        if !(self.min_radius.is_finite() && self.min_radius >= 0.0) {
            return bad(
                "min_radius",
                format!("must be finite and >= 0, got {}", self.min_radius),
            );
        }
        if !(self.scale.is_finite() && self.scale > 0.0) {
            return bad(
                "scale",
                format!("must be finite and > 0, got {}", self.scale),
            );
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid() {
        Params::DEFAULT.validate().unwrap();
        assert_eq!(Params::default(), Params::DEFAULT);
    }

    #[test]
    fn each_bad_value_names_its_parameter() {
        let cases: [(Params, &str); 9] = [
            (
                Params::DEFAULT.with_angle_threshold(200.0),
                "angle_threshold",
            ),
            (Params::DEFAULT.with_k1(65), "k1"),
            (Params::DEFAULT.with_min_vertices(7), "min_vertices"),
            (Params::DEFAULT.with_max_vertices(2), "max_vertices"),
            (
                Params::DEFAULT.with_min_vertices(16).with_max_vertices(8),
                "max_vertices",
            ),
            (Params::DEFAULT.with_cap_rings(100), "cap_rings"),
            (Params::DEFAULT.with_resolution(0.0), "resolution"),
            (Params::DEFAULT.with_min_radius(f64::NAN), "min_radius"),
            (Params::DEFAULT.with_scale(-1.0), "scale"),
        ];
        for (p, name) in cases {
            match p.validate() {
                Err(crate::Error::InvalidParam { name: n, .. }) => assert_eq!(n, name),
                other => panic!("{name}: {other:?}"),
            }
        }
    }
}
