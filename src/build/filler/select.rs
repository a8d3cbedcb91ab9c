//! Which fillers a cell gets: those estimated to add a visible share of its
//! volume, and only when together they add enough to pay for the crossings
//! they bring to the overlap pass.

use super::cone::{SAMPLE_SHRINK, SEGMENT_SHRINK, Straight, segment_track};
use super::gain::{MIN_GAIN, MIN_TOTAL_GAIN};
use crate::build::coverage::{Skipped, slices};
use crate::build::plan::Starts;
use crate::params::Params;
use crate::skeleton::Skeleton;
use crate::skeleton::track::Track;

/// One filler to build: branch `branch`'s track points `from..to`, along the
/// branch's own track or along a straight round cone.
#[derive(Debug, Clone)]
pub struct Filler {
    /// The branch it fills for.
    pub branch: u32,
    /// The first track point of its stretch.
    pub from: usize,
    /// One past the last.
    pub to: usize,
    /// The straight round cone it runs along, if it does not run along its
    /// branch's track.
    pub straight: Option<Straight>,
}

/// The fillers a cell gets, with what building them reads.
#[derive(Debug, Clone, Default)]
pub struct FillerPlan {
    /// The fillers, start fillers first in branch order, then segment
    /// fillers.
    pub fillers: Vec<Filler>,
    /// The tracks of the branches fillers run along; the others are let go
    /// here (empty), since no later stage reads them.
    pub tracks: Vec<Track>,
    /// Whether some fillers are below [`MIN_GAIN`]: a construction whose
    /// smallest filler is [`MIN_GAIN`] would leave them out.
    pub fine: bool,
}

/// The fillers of `skeleton` whose estimated gain is at least `min_gain` of
/// the cell's volume: the start fillers `starts` planned and the segment
/// fillers of the skipped `segments` (with their branch) the tubes left;
/// none unless those of at least [`MIN_GAIN`] add [`MIN_TOTAL_GAIN`]
/// together. Whatever their gain, the segment fillers without which a
/// sample would lie outside the mesh. Takes the skeleton's tracks, keeping
/// those the fillers run along.
pub fn select(
    skeleton: &mut Skeleton,
    starts: &mut Starts,
    segments: Vec<(u32, Skipped)>,
    params: &Params,
    min_gain: f64,
) -> FillerPlan {
    // None where the radii cannot be in the coordinates' units: every
    // branch then sits inside a ball far wider than the cell, and its
    // fillers would cross each other millions of times (a whole-brain axon
    // whose radius column holds codes: 9.6 million pairs, 82 s).
    let plausible = skeleton.morphology.radius_warning().is_none();
    let tracks = std::mem::take(&mut skeleton.tracks);
    let cell: f64 = tracks
        .iter()
        .map(|t| slices(t, 0, t.samples.len(), |_| 1.0))
        .sum();
    let worth = |gain: f64| plausible && gain >= min_gain * cell;
    let substantial = |gain: f64| gain >= MIN_GAIN * cell;
    let required = |s: &Skipped| plausible && s.holds_sample;
    let segments: Vec<(u32, Skipped)> = segments
        .into_iter()
        .filter(|(_, s)| worth(s.gain) || required(s))
        .collect();
    // Each branch's start filler (along the straight track for a trunk that
    // has one), then those of the segments whose contours no piece took.
    let start_fillers: Vec<(Filler, f64)> = starts
        .filler
        .iter()
        .enumerate()
        .filter_map(|(b, f)| {
            let straight = starts.filler_track[b].take();
            f.map(|(from, to, gain)| {
                let filler = Filler {
                    branch: b as u32,
                    from,
                    to,
                    straight,
                };
                (filler, gain)
            })
        })
        .filter(|(_, gain)| worth(*gain))
        .collect();
    // The fillers a sample needs neither count toward the share nor
    // depend on it.
    let gains = || {
        start_fillers.iter().map(|c| c.1).chain(
            segments
                .iter()
                .filter(|s| !required(&s.1))
                .map(|s| s.1.gain),
        )
    };
    // Together they must change the volume by a visible share: each costs
    // crossing pairs, and a cell they would change by half a percent meshes
    // twice as fast without them. Only fillers of at least `MIN_GAIN` count
    // toward that share: the finer ones are built where the larger ones
    // are, never alone. The segments' tracks are built only then.
    let built = gains().filter(|&g| substantial(g)).sum::<f64>() >= MIN_TOTAL_GAIN * cell;
    let fine = built && gains().any(|g| !substantial(g));
    // The fillers a sample needs are built whatever the others' share; the
    // others only when it is reached.
    let (start_fillers, segments) = if built {
        (start_fillers, segments)
    } else {
        let needed = segments.into_iter().filter(|s| required(&s.1)).collect();
        (Vec::new(), needed)
    };
    let segment_fillers =
        (0..segments.len()).filter_map(|i| segment_filler(skeleton, &tracks, &segments, i, params));
    let fillers: Vec<Filler> = start_fillers
        .into_iter()
        .map(|(f, _)| f)
        .chain(segment_fillers)
        .collect();
    let mut needed = vec![false; tracks.len()];
    for f in &fillers {
        needed[f.branch as usize] |= f.straight.is_none();
    }
    let tracks = tracks
        .into_iter()
        .zip(needed)
        .map(|(t, n)| if n { t } else { Track::default() })
        .collect();
    FillerPlan {
        fillers,
        tracks,
        fine,
    }
}

/// A segment whose skipped contours leave out less than this share of its
/// round cone's volume is held by its tube but for a corner.
const HELD: f64 = 0.6;

/// The filler of skipped segment `segments[i]`: its own round cone, straight,
/// drawn in ([`SEGMENT_SHRINK`], [`SAMPLE_SHRINK`]), starting flat where the
/// segment before has a filler that ends in a dome around its start.
fn segment_filler(
    skeleton: &Skeleton,
    tracks: &[Track],
    segments: &[(u32, Skipped)],
    i: usize,
    params: &Params,
) -> Option<Filler> {
    let (b, s) = (segments[i].0, segments[i].1.segment);
    let geometry = &skeleton.geometry;
    let points = &skeleton.branches[b as usize].samples;
    let (p, q) = (points[s as usize] as usize, points[s as usize + 1] as usize);
    let radii = [geometry.radius[p], geometry.radius[q]];
    let edge = tracks[b as usize].edge;
    let flat_start = i > 0 && segments[i - 1].0 == b && segments[i - 1].1.segment + 1 == s;
    let ends = (geometry.pos[p], geometry.pos[q]);
    // Drawn in further where a sample asks for the filler and the tube holds
    // most of the segment; where the tube misses most of it, the filler is
    // the segment's surface and keeps nearly its radius.
    let cone =
        std::f64::consts::PI * (0.5 * (radii[0] + radii[1])).powi(2) * ends.0.distance(ends.1);
    let skipped = segments[i].1;
    let shrink = if skipped.holds_sample && skipped.gain < HELD * cone {
        SAMPLE_SHRINK
    } else {
        SEGMENT_SHRINK
    };
    let track = segment_track(ends, radii, edge, params, flat_start, shrink)?;
    let n = track.samples.len();
    Some(Filler {
        branch: b,
        from: 0,
        to: n,
        straight: Some(Straight {
            track,
            first: s,
            flat_start,
            flat_end: false,
        }),
    })
}
