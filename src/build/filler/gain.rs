//! How much a filler adds, estimated from the slices of its contours that
//! lie outside what surrounds them, and the shares of the cell's volume
//! below which fillers are not built.

use crate::build::coverage::{fraction_outside, slices};
use crate::kernel::round_cone::RoundCone;
use crate::skeleton::track::Track;

/// A filler is built when the volume it adds is estimated at this fraction
/// of the cell's or more. Each filler costs a couple of hundred crossing
/// pairs in the overlap pass, and most (a thin branch leaving a thick one,
/// two thin ones forking) add a sliver the splice's bridge nearly covers:
/// below this share they cost more time than the volume they add is worth.
pub const MIN_GAIN: f64 = 2e-4;

/// The smallest filler the first construction builds
/// ([`crate::build::FIRST_REACH`]), as a share of the cell's volume; a cell
/// whose first union leaves crossings is built again with [`MIN_GAIN`].
/// Where a thin trace jogs every few tenths of its radius (electron
/// microscopy traces), each lost segment is a few hundredths of a percent of
/// the cell, but together they are several percent.
pub const FINE_MIN_GAIN: f64 = 1e-4;

/// Fillers are built only when together they are estimated to add this
/// fraction of the cell's volume or more. Below it they cost more time than
/// the volume they add is worth: a few fillers can double a cell's meshing
/// time (where their union fails and the cell is meshed again without
/// them) for a fraction of a percent of its volume.
pub const MIN_TOTAL_GAIN: f64 = 0.005;

/// The filler of a secondary whose tube starts at track point `start`
/// (`None`: hidden), among the round `cones` around its branch point: from
/// the contour before the first with vertices outside them up to the start
/// (the whole track for a hidden branch), with the volume outside them
/// estimated from the contours' slices. `None` when no contour before the
/// start reaches out.
pub fn span(
    track: &Track,
    start: Option<usize>,
    cones: &[RoundCone],
) -> Option<(usize, usize, f64)> {
    let end = start.unwrap_or(track.samples.len());
    // The branch point's own contour (point 0) is taken as inside.
    let mut hint = None;
    let outside: Vec<f64> = (1..end)
        .map(|i| fraction_outside(track, i, cones, &mut hint))
        .collect();
    let first = 1 + outside.iter().position(|&f| f > 0.0)?;
    let gain = slices(track, first, end, |i| outside[i - 1]);
    Some((first - 1, end, gain))
}
