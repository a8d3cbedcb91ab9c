//! Fillers: the stretch of a branch that the paper's start rule leaves out,
//! as closed tubes for the overlap pass to unite with the rest.
//!
//! A secondary's tube starts at its first contour clear of the branches
//! around its branch point (paper §3.4, [`crate::build::plan`]), and a trunk at
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
//! to cross themselves, [`crate::build::tube::pieces`]) and capped at both ends. It starts
//! inside what the branch grows out of and ends inside the tube's first band
//! (its end dome reaches past the contour before the start), so it overlaps
//! both; the overlap pass (stage 6) keeps only what lies outside
//! every other part, which is the volume the start rule left out.
//!
//! The same holds where a branch's tube breaks into pieces
//! ([`crate::build::tube::pieces`]): a piece that would cross itself ends, and the next
//! starts at the first contour clear of its volume; and where a piece skips
//! contours that would cross their predecessor, bridging them with one
//! band. Where the branch turns back on itself (a spike of one sample, a
//! zig-zag of segments a few radii long, a hairpin) the contours left out
//! are its only cover. Each original segment whose left-out contours reach
//! out of what the pieces hold gets a *segment filler*: its own round cone,
//! straight ([`cone::Straight`], [`cone::segment_track`]), domed at both
//! ends. A filler along the track would skip the same contours.
//!
//! A segment whose original sample the pieces may leave outside (it lies
//! less than [`crate::build::coverage::SAMPLE_DEPTH`] of its radius inside
//! the round cones that replace its skipped contours) gets its segment filler whatever volume it adds: the
//! surface must hold every skeleton sample. Such a *sample filler* is built
//! at [`cone::SAMPLE_SHRINK`] of the radius, which still holds the sample
//! with room and crosses less of the rest, and is left out of the gain
//! sums. Trunks get
//! their start filler from [`crate::build::plan`]: their first round cone,
//! straight.
//!
//! Sample fillers aside, only fillers estimated to add [`gain::MIN_GAIN`] of the cell's volume are
//! built, and only when together they add [`gain::MIN_TOTAL_GAIN`]: each
//! costs a couple
//! of hundred crossing pairs. Branch points on the soma
//! get none (the soma is one sphere in the reference, not its samples).
//! A filler wholly inside the rest crosses nothing and is dropped with the
//! other nested parts. The mesher removes the fillers when nothing at all
//! crosses (the one case where the overlap pass does not run). If the pass
//! leaves a crossing uncut, the cell is meshed again without the filler
//! pieces in the crossings left (up to three more times, each also without
//! those in the crossings the try before left), then, if need be, without
//! any (`pipeline::retry`); each meshing costs its own time. Filler pieces
//! left touching
//! nothing, and voids the fillers close in, are removed after the union.

pub mod cone;
pub mod gain;
pub mod select;

use crate::build::surface::Surface;
use crate::build::tube::pieces::{self, Caps};
use crate::skeleton::branch::Branch;
use select::FillerPlan;

/// Builds the fillers `plan` chose into `surface`, each piece closed and a
/// part of its own, and returns per piece its filler's index in
/// `plan.fillers` and its triangles. `branches` label the vertices.
pub fn build(
    surface: &mut Surface,
    plan: &FillerPlan,
    branches: &[Branch],
    cap_rings: u32,
) -> Vec<(u32, std::ops::Range<u32>)> {
    let mut parts = Vec::new();
    for (k, f) in plan.fillers.iter().enumerate() {
        let straight = f.straight.as_ref();
        let caps = Caps {
            first_start: true,
            later_starts: true,
            rings: match straight {
                Some(s) if s.flat_start => 0,
                _ => cap_rings,
            },
            // A trunk's straight first cone ends flat unless it ends at its
            // sample and the sample's sphere holds the dome (see
            // `plan::set_trunk_filler`).
            end_rings: match straight {
                Some(s) if s.flat_end || f.to < s.track.samples.len() => 0,
                _ => cap_rings,
            },
        };
        let along = straight.map_or(&plan.tracks[f.branch as usize], |s| &s.track);
        let track = along.prefix(f.to);
        // A straight cone's points are its first sample and the next.
        let labels = branches[f.branch as usize].vertex_labels();
        let labels = match straight {
            Some(s) => labels[s.first as usize..s.first as usize + 2].to_vec(),
            None => labels,
        };
        // Capped at every start, no piece is spliced: the anchor is unused.
        let anchor = track.samples[0].pos;
        let pieces = pieces::build_pieces(surface, &track, &labels, f.branch, f.from, anchor, caps);
        parts.extend(pieces.tubes.into_iter().map(|t| (k as u32, t.tris)));
    }
    parts
}
