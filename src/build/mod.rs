//! Stages 2 to 5, the construction: tube starts, tubes, somas, junctions and
//! fillers, in one surface whose every triangle knows its part.
//!
//! [`construct`] runs the stages, each a function from the previous stage's
//! value to the next:
//!
//! ```text
//! Skeleton ─plan::plan─▶ Starts ─tubes::build─▶ Tubes ─filler::select─▶ FillerPlan
//!          ─join_somas─▶ Open ─splice_all─▶ Spliced ─build_fillers─▶ Construction
//! ```
//!
//! Where the whole union of round cones is one star-shaped blob (radius
//! columns holding codes), [`star_hull`] meshes it instead.

pub mod coverage;
pub mod filler;
pub mod plan;
pub mod soma;
pub mod splice;
pub mod star_hull;
pub mod surface;
pub mod tube;
pub mod tubes;

use crate::error::Result;
use crate::input::morphology::Morphology;
use crate::mesh::{BuildStats, Mesh, NO_OWNER};
use crate::params::Params;
use crate::skeleton::Skeleton;
use crate::skeleton::track::{SAFE_SWEEP_CAP, SWEEP_CAP};
use filler::select::FillerPlan;
use splice::{Join, Method, Splicer};
use surface::Surface;
use tube::{Ring, Tube};
use tubes::Tubes;

/// How far a construction reaches for the union of round cones: how much
/// its tubes may widen where the trace jitters, and the smallest filler it
/// builds. The first construction reaches far ([`FIRST_REACH`]); a cell
/// whose first union leaves crossings is built again at [`SAFE_REACH`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reach {
    /// The widening cap of the tubes ([`SWEEP_CAP`]).
    pub sweep_cap: f64,
    /// The smallest filler built, as a share of the cell's volume
    /// ([`filler::gain::MIN_GAIN`]).
    pub min_gain: f64,
}

/// The first construction's reach: tubes widened up to [`SWEEP_CAP`],
/// fillers down to [`filler::gain::FINE_MIN_GAIN`].
pub const FIRST_REACH: Reach = Reach {
    sweep_cap: SWEEP_CAP,
    min_gain: filler::gain::FINE_MIN_GAIN,
};

/// The second construction's reach, for cells whose first union leaves
/// crossings: tubes widened up to [`SAFE_SWEEP_CAP`], fillers down to
/// [`filler::gain::MIN_GAIN`].
pub const SAFE_REACH: Reach = Reach {
    sweep_cap: SAFE_SWEEP_CAP,
    min_gain: filler::gain::MIN_GAIN,
};

/// The surface after stage 4: tubes and somas, with every open start still
/// to splice.
#[derive(Debug, Clone)]
pub struct Open {
    /// The tubes' and somas' vertices and triangles.
    pub surface: Surface,
    /// The tube pieces, in build order.
    pub tubes: Vec<Tube>,
    /// The open starts to splice, in build order.
    pub joins: Vec<Join>,
    /// Counts so far.
    pub stats: BuildStats,
}

/// The surface after stage 5: every start spliced.
#[derive(Debug, Clone)]
pub struct Spliced {
    /// The spliced surface.
    pub surface: Surface,
    /// The part of every triangle ([`Splicer::into_owner`]).
    pub owner: Vec<u32>,
    /// Counts so far.
    pub stats: BuildStats,
}

/// The finished construction: every part in one surface, before the overlap
/// pass unites the parts that cross.
#[derive(Debug, Clone)]
pub struct Construction {
    /// The surface.
    pub surface: Surface,
    /// The part of every triangle: a tube piece, a bridge, a filler piece,
    /// or [`NO_OWNER`] for the somas.
    pub owner: Vec<u32>,
    /// Counts.
    pub stats: BuildStats,
    /// The fillers' parts.
    pub fillers: FillerParts,
    /// The largest widening of any track's contours
    /// ([`crate::skeleton::track::Track::widest`]).
    pub widest: f64,
    /// The point the surface's positions are relative to
    /// ([`crate::mesh::frame_origin`]; zero for most cells).
    pub origin: [f64; 3],
}

/// The parts of a construction that are fillers' pieces.
#[derive(Debug, Clone, Default)]
pub struct FillerParts {
    /// Parts numbered from this one are fillers' pieces.
    pub first: u32,
    /// The filler (index into the plan's fillers) of each filler part, from
    /// `first` on: a filler is one part per tube piece.
    pub of_part: Vec<u32>,
    /// Whether some fillers are below [`filler::gain::MIN_GAIN`] (a
    /// construction at [`SAFE_REACH`] would leave them out).
    pub fine: bool,
}

impl FillerParts {
    /// Whether part `part` is a filler's piece.
    pub fn has(&self, part: u32) -> bool {
        part != NO_OWNER && part >= self.first
    }
}

impl Construction {
    /// The surface as a mesh, with the part of each face.
    pub fn into_mesh(self) -> (Mesh, Vec<u32>) {
        let (mut mesh, face_owner) = self.surface.into_mesh_with(self.stats, self.owner);
        mesh.origin = self.origin;
        (mesh, face_owner)
    }
}

/// Stages 1 to 5 on `morphology` at `reach` (see the module documentation).
///
/// # Errors
/// [`crate::Error::InvalidParam`] for a bad parameter.
pub fn construct(morphology: &Morphology, params: &Params, reach: Reach) -> Result<Construction> {
    let mut skeleton = crate::skeleton::prepare(morphology, params, reach.sweep_cap)?;
    let mut starts = plan::plan(&skeleton, params);
    let mut tubes = tubes::build(&skeleton, &starts, params);
    let segments = std::mem::take(&mut tubes.segments);
    let fillers =
        filler::select::select(&mut skeleton, &mut starts, segments, params, reach.min_gain);
    let spliced = splice_all(join_somas(tubes), params.cap_rings);
    Ok(build_fillers(spliced, &fillers, &skeleton, params))
}

/// Stage 4: each soma, joined to the trunks its triangulation takes; when its
/// triangulation fails, the plain sphere, with every trunk left to be spliced
/// onto it (added to the joins).
pub fn join_somas(tubes: Tubes) -> Open {
    let Tubes {
        mut surface,
        tubes,
        mut joins,
        somas,
        mut stats,
        ..
    } = tubes;
    for (plan, trunks) in &somas {
        let rings: Vec<Ring> = trunks.iter().map(|&t| tubes[t as usize].rings[0]).collect();
        let built = soma::build(&mut surface, &plan.sphere, &rings, plan.spacing, plan.label);
        if built.is_ok() {
            stats.soma_trunks += trunks.len() as u32;
            continue;
        }
        let _ = soma::build(&mut surface, &plan.sphere, &[], plan.spacing, plan.label);
        for (&t, ring) in trunks.iter().zip(&rings) {
            let dir = (ring.center - plan.sphere.center).normalize_or_zero();
            joins.push(Join {
                tube: t,
                toward: plan.sphere.center + plan.sphere.radius * dir,
            });
        }
    }
    Open {
        surface,
        tubes,
        joins,
        stats,
    }
}

/// Stage 5: splices every open start onto what it grows out of, in build
/// order, and counts the junctions by method.
pub fn splice_all(open: Open, cap_rings: u32) -> Spliced {
    let Open {
        mut surface,
        tubes,
        joins,
        mut stats,
    } = open;
    let mut splicer = Splicer::new(&mut surface, &tubes, &joins, cap_rings);
    for join in &joins {
        match splicer.join(&tubes, join) {
            Method::Paper => stats.junctions_paper += 1,
            Method::Moved => stats.junctions_moved += 1,
            Method::Fallback => stats.junctions_fallback += 1,
            Method::Detached => stats.junctions_detached += 1,
        }
    }
    let owner = splicer.into_owner();
    Spliced {
        surface,
        owner,
        stats,
    }
}

/// Stage 5b: the fillers `plan` chose ([`filler`]), each piece a part of
/// its own numbered after the spliced surface's parts.
pub fn build_fillers(
    spliced: Spliced,
    plan: &FillerPlan,
    skeleton: &Skeleton,
    params: &Params,
) -> Construction {
    let Spliced {
        mut surface,
        mut owner,
        mut stats,
    } = spliced;
    let first = owner
        .iter()
        .filter(|&&o| o != NO_OWNER)
        .max()
        .map_or(0, |&o| o + 1);
    stats.fillers = plan.fillers.len() as u32;
    let parts = filler::build(&mut surface, plan, &skeleton.branches, params.cap_rings);
    owner.resize(surface.tris.len(), NO_OWNER);
    let of_part = parts.iter().map(|p| p.0).collect();
    for (k, (_, tris)) in parts.into_iter().enumerate() {
        for o in &mut owner[tris.start as usize..tris.end as usize] {
            *o = first + k as u32;
        }
    }
    Construction {
        surface,
        owner,
        stats,
        fillers: FillerParts {
            first,
            of_part,
            fine: plan.fine,
        },
        widest: skeleton.widest,
        origin: skeleton.origin,
    }
}
