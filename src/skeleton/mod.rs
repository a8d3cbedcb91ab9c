//! Stage 1, the skeleton made ready for contours (paper §3.1–3.2): the cell
//! in the frame it is built in ([`geometry`]), split into branches
//! ([`branch`]), and each branch resampled ([`spline`]), framed ([`frame`])
//! and sized for contours ([`contour`], [`track`]), its straight stretches
//! thinned ([`thinning`]). [`prepare`] runs it and gives a [`Skeleton`].
pub mod branch;
pub mod contour;
pub mod frame;
pub mod geometry;
pub mod spline;
pub mod tangents;
pub mod thinning;
pub mod track;

use glam::DVec3;

use crate::error::Result;
use crate::input::morphology::Morphology;
use crate::params::Params;
use branch::{Attachment, Branch};
use geometry::{Geometry, frame_origin_of};
use track::Track;

/// A cell ready for contours: what every build stage reads.
#[derive(Debug, Clone)]
pub struct Skeleton {
    /// The morphology scaled and moved into the build frame.
    pub morphology: Morphology,
    /// Its sample positions and floored radii.
    pub geometry: Geometry,
    /// Its branches.
    pub branches: Vec<Branch>,
    /// Each branch's track, in branch order.
    pub tracks: Vec<Track>,
    /// The point the build frame is centred on: every position is relative
    /// to it ([`crate::mesh::frame_origin`]; zero for most cells).
    pub origin: [f64; 3],
    /// The largest widening of any track's contours ([`Track::widest`]; 1
    /// for none).
    pub widest: f64,
}

/// Stage 1 on `morphology`: scaled by `params.scale`, moved near the origin
/// if it lies far from it, split into branches and every branch made a track,
/// widened at most by `sweep_cap` where the trace jitters
/// ([`track::SWEEP_CAP`]).
///
/// # Errors
/// [`crate::Error::InvalidParam`] for a bad parameter.
pub fn prepare(morphology: &Morphology, params: &Params, sweep_cap: f64) -> Result<Skeleton> {
    params.validate()?;
    let m = morphology.scaled(params.scale)?;
    // A cell far from the coordinates' origin is built around its centre, so
    // the f32 positions keep the precision they have near the origin.
    let origin = frame_origin_of(morphology, params.scale);
    let m = if origin == [0.0; 3] {
        m
    } else {
        m.translated(origin.map(|c| -c))
    };
    let geometry = Geometry::new(&m, params);
    let branches = branch::identify(&m, params.angle_threshold);
    let tracks = tracks(&geometry, &branches, params, sweep_cap);
    let widest = tracks.iter().map(Track::widest).fold(1.0, f64::max);
    Ok(Skeleton {
        morphology: m,
        geometry,
        branches,
        tracks,
        origin,
        widest,
    })
}

/// Every branch resampled (Catmull-Rom) and framed, with its contour sizes,
/// widened at most by `sweep_cap` where the trace jitters ([`track::SWEEP_CAP`]),
/// and, but for trunks, without the contours its straight stretches do not
/// need ([`crate::skeleton::thinning`]).
pub fn tracks(
    geometry: &Geometry,
    branches: &[Branch],
    params: &Params,
    sweep_cap: f64,
) -> Vec<Track> {
    crate::kernel::parallel::map(branches, |b| {
        let points: Vec<DVec3> = b
            .samples
            .iter()
            .map(|&s| geometry.pos[s as usize])
            .collect();
        let radii: Vec<f64> = b
            .samples
            .iter()
            .map(|&s| geometry.radius[s as usize])
            .collect();
        let first = usize::from(matches!(b.attachment, Attachment::Soma { .. }));
        let track = Track::widened_from(&points, &radii, params, None, first, sweep_cap);
        // A trunk keeps every contour: thinned, a trunk leaving a large
        // soma loses volume along its first cone (the cause is not known;
        // `tests/soma.rs` keeps such cells within bounds).
        if first == 0 { track.thinned() } else { track }
    })
}
