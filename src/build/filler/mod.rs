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
//! both; the overlap pass ([`crate::overlap`]) keeps only what lies outside
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
//! straight ([`Straight`], [`segment_track`]), domed at both ends. A filler
//! along the track would skip the same contours. On the 48 files of the
//! corpus they brought the volume of an olivocerebellar climbing fibre from
//! 5.9 % under the union of round cones to 2.3 %, of an amoeboid microglia
//! from 4.2 % to 1.8 %, of a FlyWire neuron from 10.7 % to 7.6 %. Trunks get
//! their start filler from [`crate::build::plan`]: their first round cone,
//! straight.
//!
//! Only fillers estimated to add [`MIN_GAIN`] of the cell's volume are built,
//! and only when together they add [`MIN_TOTAL_GAIN`]: each costs a couple
//! of hundred crossing pairs. Branch points on the soma
//! get none (the soma is one sphere in the reference, not its samples).
//! A filler wholly inside the rest crosses nothing and is dropped with the
//! other nested parts. The mesher removes the fillers when nothing at all
//! crosses (the one case where the overlap pass does not run). If the pass
//! leaves a crossing uncut, the cell is meshed again without the filler
//! pieces in the crossings left (up to three more times, each also without
//! those in the crossings the try before left), then, if need be, without
//! any ([`crate::pipeline::finish`]); each meshing costs its own time (a
//! FlyWire neuron, two threads: 2.0 s with one retry, 0.58 s before it had
//! segment fillers). Filler pieces left touching
//! nothing, and voids the fillers close in, are removed after the union.

use glam::DVec3;

mod select;

pub use select::{FillerPlan, select};

use crate::build::coverage::{fraction_outside, slices};
use crate::build::surface::Surface;
use crate::build::tube::pieces::{self, Caps};
use crate::kernel::round_cone::RoundCone;
use crate::params::Params;
use crate::skeleton::branch::Branch;
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

/// A segment filler that follows another in a run of them starts flat, its
/// first contour drawn in to this fraction of the segment's radius inside
/// the dome the one before ends with. Domed too, the two would draw the
/// sphere around their shared point twice.
pub const SEGMENT_TUCK: f64 = 0.9;

/// The straight track of a segment filler (see [`Straight`]): the round cone
/// `ends` with `radii`, drawn in ([`SEGMENT_SHRINK`]), and tucked at its
/// start when it starts flat ([`SEGMENT_TUCK`]).
pub fn segment_track(
    ends: (DVec3, DVec3),
    radii: [f64; 2],
    edge: f64,
    params: &Params,
    flat_start: bool,
) -> Option<Track> {
    let mut track = straight_track(ends.0, ends.1, radii, edge, params)?;
    for r in &mut track.radii {
        *r *= SEGMENT_SHRINK;
    }
    if flat_start {
        track.radii[0] *= SEGMENT_TUCK;
    }
    Some(track)
}

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
