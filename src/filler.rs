//! Fillers: the stretch of a branch that the paper's start rule leaves out,
//! as closed tubes for the overlap pass to unite with the rest.
//!
//! A secondary's tube starts at its first contour clear of the branches
//! around its branch point (paper §3.4, [`crate::starts`]), and a trunk at
//! its first contour outside the soma. Between the branch point and that
//! contour the paper counts on the parent (or the soma) to hold the branch's
//! volume, and on the splice's bridge to join the two. That holds when the
//! branch is thin beside its parent. It fails where both are thick and the
//! skeleton is coarse: on electron-microscopy traces (fly medulla, hemibrain,
//! FlyWire) a branch of radius 20 can leave a parent of radius 17 with its
//! samples 17 apart, and its first clear contour is then 10 contours and two
//! original samples on; the union of round cones there is far outside both
//! the parent and the bridge. That was most of the volume missing on those
//! files (a third of the fly medulla neuron's).
//!
//! So a secondary also gets a *filler* where its contours before the start
//! reach out of the round cones of the branches around its branch point
//! (and of the branch point's sphere): its own contours from the one before
//! the first that reaches out up to the one before its tube's start (the
//! whole track for a hidden branch), built like any tube (pieces proven not
//! to cross themselves, [`crate::piece`]) and capped at both ends. It starts
//! inside what the branch grows out of and ends inside the tube's first band
//! (its end dome reaches past the contour before the start), so it overlaps
//! both; the overlap pass ([`crate::overlap`]) keeps only what lies outside
//! every other part, which is the volume the start rule left out.
//!
//! The same holds where a branch's tube breaks into pieces
//! ([`crate::piece`]): a piece that would cross itself ends, and the next
//! starts at the first contour clear of its volume. Where the branch turns
//! back on itself (a zig-zag of segments shorter than their radius, a
//! hairpin) the contours in between are its only cover, so the gap gets a
//! filler too, from past the piece's last ring to the next piece's start
//! ([`span_from`]; it made up 1.6 % of a von Economo spindle cell's volume
//! and 1.1 % of a fly larva neuron's). Trunks get theirs from
//! [`crate::starts`]: their first round cone, straight.
//!
//! Only fillers estimated to add [`MIN_GAIN`] of the cell's volume are built,
//! and only when together they add [`MIN_TOTAL_GAIN`]: each costs a couple
//! of hundred crossing pairs. Branch points on the soma
//! get none (the soma is one sphere in the reference, not its samples).
//! A filler wholly inside the rest crosses nothing and is dropped with the
//! other nested parts. The mesher removes the fillers when nothing at all
//! crosses (the one case where the overlap pass does not run). If the pass
//! leaves a crossing uncut, the cell is meshed again without the filler
//! pieces in the crossings left, then, if need be, without any
//! ([`crate::mesher::finish`]); each meshing costs its own time (a FlyWire
//! neuron: 1.7 s against 1.0 s without fillers). Filler pieces left touching
//! nothing, and voids the fillers close in, are removed after the union.

use crate::piece::{self, Caps};
use crate::surface::Surface;
use crate::track::Track;
use crate::volume::{Cone, fraction_outside, slices};

/// A filler is built when the volume it adds is estimated at this fraction
/// of the cell's or more. Each filler costs a couple of hundred crossing
/// pairs in the overlap pass; most (a thin branch leaving a thick one, two
/// thin ones forking) add a sliver the splice's bridge nearly covers, 0.01 %
/// of a mouse pyramidal cell's volume each.
pub const MIN_GAIN: f64 = 3e-4;

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
pub fn span(track: &Track, start: Option<usize>, cones: &[Cone]) -> Option<(usize, usize, f64)> {
    // The branch point's own contour is taken as inside.
    span_from(track, 1, 0, start.unwrap_or(track.samples.len()), cones)
}

/// The filler over track points `lo..end` among `cones`: from the contour
/// before the first with vertices outside them (but not before `floor`) up
/// to `end`, with the volume outside estimated from the contours' slices.
/// `None` when none of them reaches out.
pub fn span_from(
    track: &Track,
    lo: usize,
    floor: usize,
    end: usize,
    cones: &[Cone],
) -> Option<(usize, usize, f64)> {
    let outside: Vec<f64> = (lo..end)
        .map(|i| fraction_outside(track, i, cones))
        .collect();
    let first = lo + outside.iter().position(|&f| f > 0.0)?;
    let gain = slices(track, first, end, |i| outside[i - lo]);
    Some((first.saturating_sub(1).max(floor), end, gain))
}

/// Builds the fillers of `spans` into `surface` (closed pieces, each a part
/// of its own) and returns, per piece, its span's index and its triangles.
/// `track_of(k)` is the track span `k` runs along, `end_rings(k)` the rings
/// of its end cap.
pub fn build<'t>(
    surface: &mut Surface,
    spans: &[(u32, usize, usize)],
    track_of: impl Fn(usize) -> &'t Track,
    labels: impl Fn(u32) -> Vec<u32>,
    cap_rings: u32,
    end_rings: impl Fn(usize) -> u32,
) -> Vec<(u32, std::ops::Range<u32>)> {
    let mut parts = Vec::new();
    for (k, &(b, from, end)) in spans.iter().enumerate() {
        let caps = Caps {
            first_start: true,
            later_starts: true,
            rings: cap_rings,
            end_rings: end_rings(k),
        };
        let track = track_of(k).prefix(end);
        // Capped at every start, no piece is spliced: the anchor is unused.
        let anchor = track.samples[0].pos;
        let (pieces, _, _) =
            piece::build_pieces(surface, &track, &labels(b), b, from, anchor, caps);
        parts.extend(pieces.into_iter().map(|t| (k as u32, t.tris)));
    }
    parts
}
