//! A branch ready for contours: resampled, framed and sized (formulas 1–3).
//!
//! [`Track::new`] resamples the branch's points (see [`crate::spline`]), turns
//! the tangents into radius-scale directions, pushes the first-vertex frame
//! forward and computes each point's vertex count and polygon radius (see
//! [`crate::contour`]). [`may_follow`] is the rule for which contour may follow
//! which: the paper's "skip intersecting contours" plus a sanity check on the
//! band's shape.

use glam::DVec3;

use crate::contour::{self, DiscFrame};
use crate::params::Params;
use crate::spline::{self, Sample};

/// The resampled, framed points of a branch with their contour sizes.
#[derive(Debug, Clone)]
pub struct Track {
    /// Resampled points.
    pub samples: Vec<Sample>,
    /// First-vertex direction per point.
    pub frames: Vec<DVec3>,
    /// Vertex count per point.
    pub counts: Vec<u32>,
    /// Polygon radius per point.
    pub radii: Vec<f64>,
    /// Edge length used by formulas 1 and 3 (r_avg / resolution).
    pub edge: f64,
    /// Arc length along the resampled curve at each point.
    pub arc: Vec<f64>,
    /// For each of the branch's original points, its resampled point (a
    /// merged near-duplicate maps to the point it was merged into).
    pub originals: Vec<usize>,
}

impl Track {
    /// Resamples and frames a branch given its points and radii.
    pub fn new(points: &[DVec3], radii: &[f64], params: &Params, u0: Option<DVec3>) -> Track {
        let r_avg = radii.iter().sum::<f64>() / radii.len() as f64;
        let edge = r_avg / params.resolution;
        let mut samples = spline::resample(points, radii, edge, params.k1);
        spline::smooth_tangents(&mut samples);
        spline::reach_of_spheres(&mut samples, points, radii);
        let start_u = u0
            .map(|u| u - u.dot(samples[0].tangent) * samples[0].tangent)
            .filter(|u| u.length_squared() > 1e-12)
            .map_or_else(
                || contour::any_perpendicular(samples[0].tangent),
                DVec3::normalize,
            );
        let frames = contour::frames(&samples, start_u);
        let counts: Vec<u32> = samples
            .iter()
            .map(|s| {
                contour::vertex_count(s.radius, edge, params.min_vertices, params.max_vertices)
            })
            .collect();
        let radii = samples
            .iter()
            .zip(&counts)
            .map(|(s, &m)| contour::polygon_radius(s.radius, m))
            .collect();
        let mut arc = Vec::with_capacity(samples.len());
        let mut acc = 0.0;
        for (i, s) in samples.iter().enumerate() {
            if i > 0 {
                acc += s.pos.distance(samples[i - 1].pos);
            }
            arc.push(acc);
        }
        let mut originals = vec![0usize; points.len()];
        for (i, s) in samples.iter().enumerate() {
            if s.original {
                originals[s.source as usize] = i;
            }
        }
        // Points merged into their predecessor take its resampled index.
        for k in 1..originals.len() {
            if originals[k] < originals[k - 1] {
                originals[k] = originals[k - 1];
            }
        }
        Track {
            samples,
            frames,
            counts,
            radii,
            edge,
            arc,
            originals,
        }
    }

    /// The track cut to its first `end` points (at least one).
    pub fn prefix(&self, end: usize) -> Track {
        let end = end.clamp(1, self.samples.len());
        Track {
            samples: self.samples[..end].to_vec(),
            frames: self.frames[..end].to_vec(),
            counts: self.counts[..end].to_vec(),
            radii: self.radii[..end].to_vec(),
            edge: self.edge,
            arc: self.arc[..end].to_vec(),
            originals: self.originals.iter().map(|&k| k.min(end - 1)).collect(),
        }
    }

    /// The disc of point `i`.
    pub fn disc(&self, i: usize) -> DiscFrame {
        DiscFrame {
            center: self.samples[i].pos,
            normal: self.samples[i].tangent,
            radius: self.radii[i],
        }
    }

    /// Index of the point at arc length `s` or just after it.
    pub fn at_arc(&self, s: f64) -> usize {
        self.arc
            .partition_point(|&a| a < s)
            .min(self.samples.len() - 1)
    }

    /// Clearance margin between consecutive kept contours.
    pub fn margin(&self, a: usize, b: usize) -> f64 {
        0.02 * self.radii[a].min(self.radii[b])
    }
}

/// Whether the contour of point `k` may follow the kept contour of point `j`:
/// the two discs clear each other (the paper's intersection rule) and the band
/// between them is a sound frustum, its axis within 60° of both normals. The
/// second condition rejects contours that clear `j` only because the skeleton
/// jogged sideways in between; a band across such a jog would cut the corner
/// and be nearly edge-on to its own axis.
pub fn may_follow(track: &Track, j: usize, k: usize) -> bool {
    if !track.disc(j).clears(&track.disc(k), track.margin(j, k)) {
        return false;
    }
    let d = (track.samples[k].pos - track.samples[j].pos).normalize_or_zero();
    d.dot(track.samples[j].tangent) >= 0.5 && d.dot(track.samples[k].tangent) >= 0.5
}
