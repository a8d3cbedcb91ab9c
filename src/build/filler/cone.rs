//! Fillers along a straight round cone of the skeleton rather than their
//! branch's track: a trunk's first cone, a segment whose contours the tube
//! skipped.

use glam::DVec3;

use crate::params::Params;
use crate::skeleton::track::Track;

/// A filler's own track, when it does not run along its branch's: one round
/// cone of the skeleton, straight, from the branch's original point `first`
/// to the next (a trunk's first cone, [`crate::build::plan`]; a segment whose
/// contours were skipped, [`crate::build::tube::pieces::Pieces::segments`]).
#[derive(Debug, Clone)]
pub struct Straight {
    /// The cone's track.
    pub track: Track,
    /// Index of its first point among its branch's original points.
    pub first: u32,
    /// Whether it starts flat, drawn in: the filler of the segment before
    /// ends in a dome around its start.
    pub flat_start: bool,
    /// Whether it ends flat though it ends at its sample: its last contour
    /// is wider than the sample's own sphere ([`dome_leaves_sphere`]).
    pub flat_end: bool,
}

/// Whether a dome on the last contour of `track` would stand out of the
/// sphere of radius `own` around its last point, the skeleton's sample: the
/// contour is wider where a neighbouring sphere reaches over the sample
/// ([`crate::skeleton::spline::reach_of_spheres`]), as where a trunk's first sample
/// lies deep inside its soma sample's sphere. A dome there of the contour's
/// radius bulges past that sphere too: on a trunk 3.9 units from a soma
/// sample of radius 6.6 the dome (radius 5.0) added 11 % to the volume of
/// the union of round cones.
pub fn dome_leaves_sphere(track: &Track, own: f64) -> bool {
    track
        .samples
        .last()
        .is_some_and(|s| s.radius > own * (1.0 + 1e-9))
}

/// The straight track of the round cone `p`–`q` with radii `radii`, sampled
/// like a track of edge length `edge`: at the cone's own mean radius its
/// contours would stand a radius apart, and their flat bands cut far inside
/// where the cone meets a much thicker neighbour (a trunk leaving its
/// sphere). `None` for a cone of no length.
pub fn straight_track(
    p: DVec3,
    q: DVec3,
    radii: [f64; 2],
    edge: f64,
    params: &Params,
) -> Option<Track> {
    if p.distance(q) <= 0.0 || edge <= 0.0 {
        return None;
    }
    let params = Params {
        resolution: 0.5 * (radii[0] + radii[1]) / edge,
        ..*params
    };
    Some(Track::new(&[p, q], &radii, &params, None))
}

/// A segment filler's cone is drawn in to this fraction of the skeleton's
/// radii. Where the tube holds the segment after all, the filler's surface
/// then lies inside the tube's and meets it at an angle, instead of running
/// along it, the same cone drawn twice by polygons out of phase: such
/// grazing contacts are where the overlap pass fails to cut, and a cell
/// whose fillers it cannot unite is meshed again without some of them. On
/// a FlyWire neuron drawn in cones cross the rest in 35,512 pairs instead
/// of 42,850. It gives up a tenth (1 − 0.95²) of the cross-section a
/// filler adds.
pub const SEGMENT_SHRINK: f64 = 0.95;

/// The cone of a segment filler built only because a sample would otherwise lie
/// outside the mesh is drawn in further, to this fraction of the skeleton's
/// radii: such a segment is mostly held by its tube (which cuts the corner
/// at the sample), and a filler surface close to the tube's meets it in
/// grazing contacts the overlap pass fails to cut, which costs the cell a
/// second construction. Its end dome still holds the sample at its centre.
pub const SAMPLE_SHRINK: f64 = 0.8;

/// A segment filler that follows another in a run of them starts flat, its
/// first contour drawn in to this fraction of the segment's radius inside
/// the dome the one before ends with. Domed too, the two would draw the
/// sphere around their shared point twice.
pub const SEGMENT_TUCK: f64 = 0.9;

/// The straight track of a segment filler (see [`Straight`]): the round cone
/// `ends` with `radii`, drawn in to `shrink` of them ([`SEGMENT_SHRINK`] or
/// [`SAMPLE_SHRINK`]), and tucked at its start when it starts flat
/// ([`SEGMENT_TUCK`]).
pub fn segment_track(
    ends: (DVec3, DVec3),
    radii: [f64; 2],
    edge: f64,
    params: &Params,
    flat_start: bool,
    shrink: f64,
) -> Option<Track> {
    let mut track = straight_track(ends.0, ends.1, radii, edge, params)?;
    for r in &mut track.radii {
        *r *= shrink;
    }
    if flat_start {
        track.radii[0] *= SEGMENT_TUCK;
    }
    Some(track)
}
