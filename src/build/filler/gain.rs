//! How much a filler adds, estimated from the slices of its contours that
//! lie outside what surrounds them, and the shares of the cell's volume
//! below which fillers are not built.

use crate::build::coverage::{fraction_outside, slices};
use crate::kernel::round_cone::RoundCone;
use crate::skeleton::track::Track;

/// A filler is built when the volume it adds is estimated at this fraction
/// of the cell's or more. Each filler costs a couple of hundred crossing
/// pairs in the overlap pass; most (a thin branch leaving a thick one, two
/// thin ones forking) add a sliver the splice's bridge nearly covers, 0.01 %
/// of a mouse pyramidal cell's volume each. Over the 48 corpus files, 0.02 %
/// (rather than 0.03 %) brings two more within 3 % of the union's volume for
/// 3 % more survey time (about 5 % on one thread); 0.01 % brings the same two
/// for 61 % more. On the synthetic scale tree 0.02 % costs 30 %: its extra
/// fillers bring another whole-mesh round of the overlap pass (benches/README,
/// "Smaller fillers").
pub const MIN_GAIN: f64 = 2e-4;

/// The smallest filler the first construction builds
/// ([`crate::pipeline::FIRST_REACH`]), as a share of the cell's volume; a
/// cell whose first union leaves crossings is built again with
/// [`MIN_GAIN`]. Where a thin trace jogs every few tenths of its radius
/// (a fly larva neuron, radius 0.2 and samples 0.14 apart), each lost
/// segment is a few hundredths of a percent of the cell but together they
/// are several percent: 845 segments below [`MIN_GAIN`] were estimated at
/// 8.5 % of its volume, and the cell came 5.5 % under the union of round
/// cones. At 0.01 % it comes 2.0 % under (benches/README, "Finer fillers").
pub const FINE_MIN_GAIN: f64 = 1e-4;

/// Fillers are built only when together they are estimated to add this
/// fraction of the cell's volume or more. Below it they cost more time than
/// the volume they add is worth: one filler estimated at 0.03 % of the
/// cell doubled the meshing time of a 26,000-sample mouse cell (its union
/// failed and the cell was meshed again without it), four at 0.15 % did
/// the same to a retinal ganglion cell.
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
