//! The pipeline, end to end: morphology → branches → tubes → mesh.
//!
//! Branch tubes are independent, so they are built in parallel (each into its
//! own [`Surface`]) and appended in branch order, which keeps the output
//! identical whatever the number of threads.

use crate::build::filler::Straight;
use crate::build::plan::{SomaPlan, Starts};
use crate::build::soma;
use crate::build::splice::{Join, Method, Splicer};
use crate::build::surface::Surface;
use crate::build::tube::pieces::{self, Caps};
use crate::error::Result;
use crate::input::morphology::Morphology;
use crate::mesh::{BuildStats, Mesh};
use crate::params::Params;
use crate::skeleton::branch::{self, Attachment, Branch};
use crate::skeleton::geometry::{Geometry, frame_origin_of};
use crate::skeleton::track::{SAFE_SWEEP_CAP, SWEEP_CAP, Track};
use crate::skeleton::tracks;

use crate::build::tube::{Ring, Tube};

/// Branches whose tubes are built (in parallel) before they are appended to
/// the cell's surface.
const TUBE_CHUNK: usize = 256;

/// How far a construction reaches for the union of round cones: how much
/// its tubes may widen where the trace jitters, and the smallest filler it
/// builds. The first construction reaches far ([`FIRST_REACH`]); a cell
/// whose first union leaves crossings is built again at [`SAFE_REACH`]
/// ([`unite`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reach {
    /// The widening cap of the tubes ([`SWEEP_CAP`]).
    pub sweep_cap: f64,
    /// The smallest filler built, as a share of the cell's volume
    /// ([`crate::build::filler::MIN_GAIN`]).
    pub min_gain: f64,
}

/// The first construction's reach: tubes widened up to [`SWEEP_CAP`],
/// fillers down to [`crate::build::filler::FINE_MIN_GAIN`].
pub const FIRST_REACH: Reach = Reach {
    sweep_cap: SWEEP_CAP,
    min_gain: crate::build::filler::FINE_MIN_GAIN,
};

/// The second construction's reach, for cells whose first union leaves
/// crossings: tubes widened up to [`SAFE_SWEEP_CAP`], fillers down to
/// [`crate::build::filler::MIN_GAIN`].
pub const SAFE_REACH: Reach = Reach {
    sweep_cap: SAFE_SWEEP_CAP,
    min_gain: crate::build::filler::MIN_GAIN,
};

/// Meshes an SWC file with `params` (reading, cleaning and meshing).
///
/// # Errors
/// [`crate::Error::Io`] or [`crate::Error::Swc`] for the file,
/// [`crate::Error::InvalidParam`] for a bad parameter.
///
/// # Example
/// ```
/// let mesh = neuromesh::mesh_swc("tests/data/y_bifurcation.swc", &neuromesh::Params::default())?;
/// assert!(mesh.check().is_closed());
/// # Ok::<(), neuromesh::Error>(())
/// ```
pub fn mesh_swc(path: impl AsRef<std::path::Path>, params: &Params) -> Result<Mesh> {
    params.validate()?;
    mesh_morphology(&Morphology::from_swc(path)?, params)
}

/// Meshes a morphology with `params`.
///
/// # Errors
/// [`crate::Error::InvalidParam`] for a bad parameter.
pub fn mesh_morphology(morphology: &Morphology, params: &Params) -> Result<Mesh> {
    params.validate()?;
    // A union of round cones that is one star-shaped blob (radius codes
    // swelling every sphere past the cell) is meshed whole ([`crate::build::star_hull`]).
    let origin = frame_origin_of(morphology, params.scale);
    if let Some(mut mesh) = crate::build::star_hull::mesh(morphology, params.scale, origin) {
        mesh.origin = origin;
        return Ok(mesh);
    }
    unite(morphology, params, construct(morphology, params)?)
}

/// Step 6 on `stage`, constructed from `morphology` by [`construct`]: the
/// mesh with its overlaps resolved and fillers united. Tubes widened to
/// [`SWEEP_CAP`] and the smaller fillers [`FIRST_REACH`] builds can crowd
/// the fillers on a thick trunk past what the overlap pass cuts; where the
/// first union leaves crossings the cell is built again at [`SAFE_REACH`]
/// and finished there, retries and all ([`finish`]). Only such cells pay
/// for the second construction, and only if a contour was widened past the
/// safe cap or a filler below [`crate::build::filler::MIN_GAIN`] was built:
/// otherwise the second would be the first again, and the retries go on
/// from the first.
///
/// # Errors
/// [`crate::Error::InvalidParam`] for a bad parameter.
pub fn unite(morphology: &Morphology, params: &Params, mut stage: TubeStage) -> Result<Mesh> {
    // Where no contour was widened past the safe cap, building again at it
    // would give the same stage, and the same first try: the retries go on
    // from this one.
    let widened_past_safe = stage.widest > SAFE_SWEEP_CAP * (1.0 + 1e-9);
    stage.tracks = Vec::new();
    let fine_fillers = stage.fine_fillers;
    let first = first_try(stage);
    if let FirstTry::Clean(mesh) = first {
        return Ok(mesh);
    }
    if !widened_past_safe && !fine_fillers {
        return retry(first, || construct_with(morphology, params, FIRST_REACH));
    }
    let safe = || construct_with(morphology, params, SAFE_REACH);
    finish(safe()?, safe)
}

/// Step 6 on a constructed stage: the mesh, with the overlaps resolved and
/// the fillers united with the rest (or dropped; see [`crate::build::filler`]).
/// `rebuild` constructs the same stage again; it is called only when the
/// fillers leave crossings the pass cannot cut, so the first try works on the
/// mesh itself rather than on a copy kept for that rare case.
///
/// # Errors
/// What `rebuild` returns.
pub fn finish(stage: TubeStage, rebuild: impl FnOnce() -> Result<TubeStage>) -> Result<Mesh> {
    retry(first_try(stage), rebuild)
}

/// [`finish`] after its first try: the mesh it made, or the retries that
/// leave out the fillers in the crossings it left, on the stage `rebuild`
/// constructs again.
fn retry(first: FirstTry, rebuild: impl FnOnce() -> Result<TubeStage>) -> Result<Mesh> {
    let (stuck, first_part, filler_of_part) = match first {
        FirstTry::Clean(mesh) | FirstTry::Crossed(mesh) => return Ok(mesh),
        FirstTry::Stuck {
            stuck,
            first_part,
            of_part,
        } => (stuck, first_part, of_part),
    };
    // The fillers add crossings; should the pass fail to cut some, the cell
    // is meshed again without the filler pieces in them (and again, up to
    // `MAX_FILLER_RETRIES` times, without those in the crossings each try
    // leaves), and should that fail too, as the paper builds it, without
    // fillers, rather than left crossing itself.
    let fillers = Fillers {
        first_part,
        of_part: &filler_of_part,
    };
    // Construction is deterministic: the rebuilt mesh numbers its faces and
    // parts as the first did, so `stuck` and `fillers` still name them.
    let (mesh, face_owner, ..) = rebuild()?.into_mesh();
    let mut stuck = stuck;
    for attempt in 0..MAX_FILLER_RETRIES {
        if stuck.is_empty()
            || (attempt > 0 && stuck.len() as f64 > MAX_STUCK_SHARE * filler_of_part.len() as f64)
        {
            break;
        }
        let (fewer, resolved) = fillers.unite_without(mesh.clone(), face_owner.clone(), |o| {
            stuck.binary_search(&o).is_ok()
        });
        if resolved.outcome.pairs_left == 0 {
            return Ok(fewer);
        }
        let before = stuck.len();
        stuck.extend(
            resolved
                .left_parts
                .iter()
                .copied()
                .filter(|&o| fillers.has(o)),
        );
        stuck.sort_unstable();
        stuck.dedup();
        if stuck.len() == before {
            break;
        }
    }
    Ok(fillers
        .unite_without(mesh, face_owner, |o| fillers.has(o))
        .0)
}

/// How the first union of a constructed stage went.
enum FirstTry {
    /// Nothing is left crossing.
    Clean(Mesh),
    /// A stage without fillers whose overlaps the pass left crossing: there
    /// is nothing to leave out and try again.
    Crossed(Mesh),
    /// The fillers' union left crossings: the filler parts in them, sorted,
    /// and the stage's filler parts (from `first_part`, each of the filler
    /// `of_part[part - first_part]`).
    Stuck {
        stuck: Vec<u32>,
        first_part: u32,
        of_part: Vec<u32>,
    },
}

/// The stage's mesh with its overlaps resolved and all its fillers united.
fn first_try(stage: TubeStage) -> FirstTry {
    let (mesh, face_owner, first_part, of_part) = stage.into_mesh();
    let has_fillers = face_owner.last().is_some_and(|&o| is_filler(o, first_part));
    if !has_fillers {
        let mut mesh = mesh;
        resolve_overlaps_owned(&mut mesh, face_owner);
        if mesh.stats.overlap_pairs > 0 && mesh.stats.overlap_pairs_left == 0 {
            drop_shells(&mut mesh, |_| false);
        }
        return if mesh.stats.overlap_pairs_left == 0 {
            FirstTry::Clean(mesh)
        } else {
            FirstTry::Crossed(mesh)
        };
    }
    let fillers = Fillers {
        first_part,
        of_part: &of_part,
    };
    let (united, resolved) = fillers.unite_without(mesh, face_owner, |_| false);
    if resolved.outcome.pairs_left == 0 {
        return FirstTry::Clean(united);
    }
    // Sorted, once each, as `left_parts` is.
    let stuck: Vec<u32> = resolved
        .left_parts
        .iter()
        .copied()
        .filter(|&o| fillers.has(o))
        .collect();
    FirstTry::Stuck {
        stuck,
        first_part,
        of_part,
    }
}

/// How many times the mesher unites the fillers again, each time also
/// without those in the crossings the last try left, before it gives all of
/// them up. Which contacts the pass fails to cut shifts from try to try. In
/// trials on a FlyWire neuron of the corpus (with more, larger segment
/// fillers than built now) the tries without 15 and 17 fillers failed
/// elsewhere and the one without 23 held, keeping 272; a single retry
/// would have given all of them up, leaving the cell 18.4 % under the union
/// of round cones instead of 8.2 %.
const MAX_FILLER_RETRIES: usize = 3;

/// After its first retry, the mesher unites the fillers again only while
/// those left out are at most this share of their pieces. More means the
/// contacts are degenerate all over, and leaving out the pieces in the
/// crossings each try leaves does not get through them: a fly larva neuron
/// with its coordinates rounded to a 1 µm grid and radii to 0.5 µm had 148
/// of 634 filler pieces in the crossings its first try left, then 281 and
/// 330 in all, the retries costing 5.3, 4.3 and 2.6 s (6.8 s the first
/// try), to end without fillers anyway. The FlyWire trials above left out
/// 8 %; the corpus's own files never retry.
///
/// The first retry is made whatever the share: fillers crowding one thick
/// trunk can leave one cluster of crossings uncut, and all of them with it.
/// The fly medulla neuron rounded to the grid left 73 of 155 fillers in
/// such a cluster; united without those, it came 12.3 % under the union of
/// round cones' volume instead of 29.8 % without any filler (the grid-rounded
/// larva, whose retry fails, took 9.1 s instead of 6.2).
const MAX_STUCK_SHARE: f64 = 0.125;

/// The fillers' parts of a mesh: parts from `first_part` on, each of the
/// filler `of_part[part - first_part]`.
struct Fillers<'a> {
    first_part: u32,
    of_part: &'a [u32],
}

impl Fillers<'_> {
    /// Whether part `o` is a filler's.
    fn has(&self, o: u32) -> bool {
        is_filler(o, self.first_part)
    }

    /// `mesh` (whose face `f` is of part `owner[f]`) without the faces
    /// of the filler parts `dropped` accepts, its overlaps resolved, and what
    /// the pass told. Where nothing crosses, the fillers lie inside the rest
    /// and are removed; where the union was built, so are the shells
    /// [`drop_shells`] names. `stats.fillers` counts the fillers kept.
    fn unite_without(
        &self,
        mut out: Mesh,
        mut owner: Vec<u32>,
        dropped: impl Fn(u32) -> bool,
    ) -> (Mesh, crate::overlap::Resolved) {
        let gone = |o: u32| self.has(o) && dropped(o);
        if owner.iter().any(|&o| gone(o)) {
            out.retain_faces(|f| !gone(owner[f]));
            owner.retain(|&o| !gone(o));
        }
        let resolved = crate::overlap::resolve_owned(&mut out, owner);
        out.stats.overlap_pairs = resolved.outcome.pairs;
        out.stats.overlap_pairs_left = resolved.outcome.pairs_left;
        let mut kept: Vec<u32> = (0..self.of_part.len() as u32)
            .filter(|&k| !dropped(self.first_part + k))
            .map(|k| self.of_part[k as usize])
            .collect();
        if resolved.outcome.pairs == 0 {
            // The pass changed nothing: the owners it hands back are those
            // it was given.
            out.retain_faces(|f| !self.has(resolved.owner[f]));
            kept.clear();
        } else if resolved.outcome.pairs_left == 0 && !kept.is_empty() {
            drop_shells(&mut out, |f| self.has(resolved.owner[f]));
        }
        kept.sort_unstable();
        kept.dedup();
        out.stats.fillers = kept.len() as u32;
        (out, resolved)
    }
}

/// Removes the closed shells a union can leave that are not membrane: voids
/// (inward components, negative signed volume) and, with fillers, filler
/// pieces that touch nothing else (components whose every face `filler`
/// names).
///
/// A void is the inside of a ring of parts that crossed each other all
/// round it: fillers and the tubes around them (found by the random trees),
/// or in a tangle of traced branches (a jittered copy of a 260-tree BigNeuron
/// file enclosed one of 0.035 µm³ among its crossing tubes). A cell's
/// membrane has no cavity, whether the polygons made it or the round cones
/// have it too, and an inward shell would make the mesh fail "outward": it
/// is filled. That adds its volume (and drops its area) against the union of
/// round cones, a share of a share of a percent.
fn drop_shells(mesh: &mut Mesh, filler: impl Fn(usize) -> bool) {
    let component = crate::kernel::disjoint_sets::face_components(&mesh.faces, mesh.vertices.len());
    let count = component.iter().map(|&c| c as usize + 1).max().unwrap_or(0);
    if count < 2 {
        return;
    }
    let mut volume = vec![0.0f64; count];
    let view = mesh.view();
    let c = view.center();
    for (f, &k) in component.iter().enumerate() {
        let [a, b, d] = view.triangle(f, c);
        volume[k as usize] += crate::kernel::vector::dot(a, crate::kernel::vector::cross(b, d));
    }
    let mut filler_only = vec![true; count];
    for (f, &k) in component.iter().enumerate() {
        if !filler(f) {
            filler_only[k as usize] = false;
        }
    }
    let drop: Vec<bool> = (0..count)
        .map(|k| volume[k] < 0.0 || filler_only[k])
        .collect();
    if !drop.contains(&true) || drop.iter().all(|&d| d) {
        return;
    }
    mesh.retain_faces(|f| !drop[component[f] as usize]);
}

/// Whether a face of part `owner` belongs to a filler.
fn is_filler(owner: u32, filler_parts: u32) -> bool {
    owner != crate::overlap::NO_OWNER && owner >= filler_parts
}

/// Steps 1 to 5: tubes, somas, junctions and fillers, before overlaps are
/// resolved.
///
/// # Errors
/// [`crate::Error::InvalidParam`] for a bad parameter.
pub fn construct(morphology: &Morphology, params: &Params) -> Result<TubeStage> {
    construct_with(morphology, params, FIRST_REACH)
}

/// [`construct`] at `reach`: how much the tubes widen where the trace
/// jitters and the smallest filler built.
///
/// # Errors
/// [`crate::Error::InvalidParam`] for a bad parameter.
pub fn construct_with(morphology: &Morphology, params: &Params, reach: Reach) -> Result<TubeStage> {
    let mut stage = build_tubes_with(morphology, params, reach)?;
    build_somas(&mut stage);
    splice_all(&mut stage, params);
    build_fillers(&mut stage, params);
    Ok(stage)
}

/// Step 6: where parts of the mesh cross each other, the boundary of their
/// union replaces them ([`crate::overlap`]); counted in the stats.
pub fn resolve_overlaps(mesh: &mut Mesh, face_owner: &[u32]) {
    resolve_overlaps_owned(mesh, face_owner.to_vec());
}

/// [`resolve_overlaps`], handing the owners over rather than copying them.
fn resolve_overlaps_owned(mesh: &mut Mesh, face_owner: Vec<u32>) {
    let outcome = crate::overlap::resolve_owned(mesh, face_owner).outcome;
    mesh.stats.overlap_pairs = outcome.pairs;
    mesh.stats.overlap_pairs_left = outcome.pairs_left;
}

/// The whole construction with its intermediate structures (branches and tubes
/// with their rings), for inspection and debugging tools. For a cell far from
/// the coordinates' origin the surface's positions are relative to the point
/// [`crate::mesh::frame_origin`] picks for its bounds.
///
/// # Errors
/// [`crate::Error::InvalidParam`] for a bad parameter.
pub fn build(
    morphology: &Morphology,
    params: &Params,
) -> Result<(Surface, Vec<Branch>, Vec<Tube>, BuildStats)> {
    let TubeStage {
        surface,
        branches,
        tubes,
        stats,
        ..
    } = construct(morphology, params)?;
    Ok((surface, branches, tubes, stats))
}

/// Step 4: each soma, joined to the trunks its triangulation takes; when its
/// triangulation fails, the plain sphere, with every trunk left to be spliced
/// onto it (added to the stage's joins).
pub fn build_somas(stage: &mut TubeStage) {
    let TubeStage {
        surface,
        tubes,
        joins,
        somas,
        stats,
        ..
    } = stage;
    for (plan, trunks) in somas.iter() {
        let rings: Vec<Ring> = trunks.iter().map(|&t| tubes[t as usize].rings[0]).collect();
        let built = soma::build(surface, &plan.sphere, &rings, plan.spacing, plan.label);
        if built.is_ok() {
            stats.soma_trunks += trunks.len() as u32;
            continue;
        }
        let _ = soma::build(surface, &plan.sphere, &[], plan.spacing, plan.label);
        for (&t, ring) in trunks.iter().zip(&rings) {
            let dir = (ring.center - plan.sphere.center).normalize_or_zero();
            joins.push(Join {
                tube: t,
                toward: plan.sphere.center + plan.sphere.radius * dir,
            });
        }
    }
    somas.clear();
}

/// Step 5: splices every open start onto what it grows out of, in build
/// order, and counts the junctions by method.
pub fn splice_all(stage: &mut TubeStage, params: &Params) {
    let mut splicer = Splicer::new(
        &mut stage.surface,
        &stage.tubes,
        &stage.joins,
        params.cap_rings,
    );
    for join in &stage.joins {
        match splicer.join(&stage.tubes, join) {
            Method::Paper => stage.stats.junctions_paper += 1,
            Method::Moved => stage.stats.junctions_moved += 1,
            Method::Fallback => stage.stats.junctions_fallback += 1,
            Method::Detached => stage.stats.junctions_detached += 1,
        }
    }
    stage.owner = splicer.into_owner();
    stage.joins.clear();
}

/// Step 5b: the fillers ([`crate::build::filler`]), each piece a part of its own
/// numbered from [`TubeStage::filler_parts`].
pub fn build_fillers(stage: &mut TubeStage, params: &Params) {
    let base = stage
        .owner
        .iter()
        .filter(|&&o| o != crate::overlap::NO_OWNER)
        .max()
        .map_or(0, |&o| o + 1);
    stage.filler_parts = base;
    stage.stats.fillers = stage.fillers.len() as u32;
    let TubeStage {
        surface,
        branches,
        tracks,
        fillers,
        filler_straight,
        owner,
        filler_of_part,
        ..
    } = stage;
    let straight = |k: usize| filler_straight[k].as_ref();
    let parts = crate::build::filler::build(
        surface,
        fillers,
        |k| straight(k).map_or(&tracks[fillers[k].0 as usize], |s| &s.track),
        // A straight cone's points are its first sample and the next.
        |k| {
            let labels = sample_labels(&branches[fillers[k].0 as usize]);
            match straight(k) {
                Some(s) => labels[s.first as usize..s.first as usize + 2].to_vec(),
                None => labels,
            }
        },
        |k| match straight(k) {
            Some(s) if s.flat_start => 0,
            _ => params.cap_rings,
        },
        // A trunk's straight first cone ends flat unless it ends at its
        // sample and the sample's sphere holds the dome (see
        // `starts::set_trunk_filler`).
        |k| match straight(k) {
            Some(s) if s.flat_end || fillers[k].2 < s.track.samples.len() => 0,
            _ => params.cap_rings,
        },
    );
    owner.resize(surface.tris.len(), crate::overlap::NO_OWNER);
    *filler_of_part = parts.iter().map(|p| p.0).collect();
    for (k, (_, tris)) in parts.into_iter().enumerate() {
        for o in &mut owner[tris.start as usize..tris.end as usize] {
            *o = base + k as u32;
        }
    }
}

/// The sample each contour vertex of branch `b` is labelled with: a trunk's
/// vertices carry neurite samples, never the soma's (the soma sample is only
/// where the trunk's track begins).
fn sample_labels(b: &Branch) -> Vec<u32> {
    let mut labels = b.samples.clone();
    if matches!(b.attachment, Attachment::Soma { .. }) && labels.len() > 1 {
        labels[0] = labels[1];
    }
    labels
}

/// The surface before splicing: every branch's tube pieces, closed at their
/// ends except where a join will splice them (secondary starts, later pieces)
/// or a soma will join them (trunks).
#[derive(Debug, Clone)]
pub struct TubeStage {
    /// The pieces' vertices and triangles.
    pub surface: Surface,
    /// The branches of the morphology.
    pub branches: Vec<Branch>,
    /// The pieces, in build order, with their triangle ranges.
    pub tubes: Vec<Tube>,
    /// The open starts still to be spliced.
    pub joins: Vec<Join>,
    /// Each soma to build, with the tubes whose first ring it joins.
    pub somas: Vec<(SomaPlan, Vec<u32>)>,
    /// Counts so far.
    pub stats: BuildStats,
    /// The tube piece of every triangle, once spliced (empty before).
    pub owner: Vec<u32>,
    /// The tracks of the branches the fillers run along (empty for the
    /// others, which no step after the tubes reads: on a million-sample
    /// tree they were 0.8 GB of the splicing's peak memory).
    pub tracks: Vec<Track>,
    /// The largest widening of any track's contours
    /// ([`Track::widest`]).
    pub widest: f64,
    /// The fillers to build: branch and its track points `from..to`
    /// ([`crate::build::filler`]).
    pub fillers: Vec<(u32, usize, usize)>,
    /// Per filler, the straight round cone it runs along, if it does not
    /// run along its branch's track.
    pub filler_straight: Vec<Option<Straight>>,
    /// Parts numbered from this one are fillers (set when they are built).
    pub filler_parts: u32,
    /// The filler (index in `fillers`) of each filler part, from
    /// `filler_parts` on: a filler is one part per tube piece.
    pub filler_of_part: Vec<u32>,
    /// The point the stage is built around: the surface's positions are
    /// relative to it ([`crate::mesh::frame_origin`]; zero for most cells).
    pub origin: [f64; 3],
    /// Whether some of `fillers` are below [`crate::build::filler::MIN_GAIN`]:
    /// a stage at [`SAFE_REACH`] would leave them out.
    pub fine_fillers: bool,
}

impl TubeStage {
    /// The surface as a mesh, with the part of each face, the first filler
    /// part and the filler of each filler part.
    fn into_mesh(self) -> (Mesh, Vec<u32>, u32, Vec<u32>) {
        let (mut mesh, face_owner) = self.surface.into_mesh_with(self.stats, self.owner);
        mesh.origin = self.origin;
        (mesh, face_owner, self.filler_parts, self.filler_of_part)
    }
}

/// Steps 1 to 3 of the pipeline: branches, tracks, first contours and tubes.
///
/// # Errors
/// [`crate::Error::InvalidParam`] for a bad parameter.
pub fn build_tubes(morphology: &Morphology, params: &Params) -> Result<TubeStage> {
    build_tubes_with(morphology, params, FIRST_REACH)
}

/// [`build_tubes`] at `reach`: the tubes widened at most by its
/// `sweep_cap` where the trace jitters ([`SWEEP_CAP`]), the fillers down to
/// its `min_gain`.
///
/// # Errors
/// [`crate::Error::InvalidParam`] for a bad parameter.
pub fn build_tubes_with(
    morphology: &Morphology,
    params: &Params,
    reach: Reach,
) -> Result<TubeStage> {
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
    let mut stats = BuildStats {
        branches: branches.len() as u32,
        ..BuildStats::default()
    };
    // 1. Resample and frame every branch.
    let tracks = tracks(&geometry, &branches, params, reach.sweep_cap);
    // 2. Where each branch's tube starts, and which trunks each soma takes.
    let Starts {
        start: starts,
        spliced_trunk,
        somas,
        filler,
        mut filler_track,
    } = crate::build::plan::plan(&m, &geometry, &branches, &tracks, params);
    // 3. Tubes, in parallel, appended in branch order.
    let jobs: Vec<u32> = (0..branches.len() as u32)
        .filter(|&i| starts[i as usize].is_some())
        .collect();
    stats.branches_hidden = (branches.len() - jobs.len()) as u32;
    let build_one = |&id: &u32| {
        let b = &branches[id as usize];
        let track = &tracks[id as usize];
        let caps = Caps {
            // Secondaries are spliced and trunks joined to their soma.
            first_start: b.attachment == Attachment::Root,
            later_starts: false,
            rings: params.cap_rings,
            end_rings: params.cap_rings,
        };
        let mut surface = Surface::with_capacity(track.counts.iter().map(|&m| m as usize).sum());
        let anchor = geometry.pos[b.samples[0] as usize];
        let start = starts[id as usize].unwrap_or(0);
        let labels = sample_labels(b);
        let pieces = pieces::build_pieces(&mut surface, track, &labels, id, start, anchor, caps);
        (surface, pieces)
    };
    // Room for the whole cell at once: growing by doubling copied the surface
    // several times over (`Surface::append` was 6 % of the Allen 177300
    // cell's profile). Caps and bridges add a few per cent to the rings'
    // vertices.
    let ring_vertices: usize = jobs
        .iter()
        .map(|&id| {
            tracks[id as usize]
                .counts
                .iter()
                .map(|&m| m as usize)
                .sum::<usize>()
        })
        .sum();
    let mut surface = Surface::with_capacity(ring_vertices + ring_vertices / 8 + 1024);
    let mut tubes: Vec<Tube> = Vec::new();
    let mut joins: Vec<Join> = Vec::new();
    let mut first_tube: Vec<Option<u32>> = vec![None; branches.len()];
    let mut segments: Vec<(u32, (u32, f64))> = Vec::new();
    // In chunks of branches: the per-branch surfaces of one chunk at a time
    // are alive beside the whole one, not those of the whole cell (which
    // doubled the peak memory of a million-sample tree).
    for chunk in jobs.chunks(TUBE_CHUNK) {
        let built: Vec<(Surface, pieces::Pieces)> = crate::kernel::parallel::map(chunk, build_one);
        for ((local, pieces), &id) in built.into_iter().zip(chunk) {
            let (v0, t0) = surface.append(&local);
            stats.contours_skipped += pieces.skipped;
            segments.extend(pieces.segments.into_iter().map(|g| (id, g)));
            for (piece_index, mut t) in pieces.tubes.into_iter().enumerate() {
                t.rings.truncate(crate::build::tube::KEPT_RINGS);
                t.rings.shrink_to_fit();
                for r in &mut t.rings {
                    r.first += v0;
                }
                for b in &mut t.bands {
                    *b += t0;
                }
                t.start_cap = t.start_cap.start + t0..t.start_cap.end + t0;
                t.end_cap = t.end_cap.start + t0..t.end_cap.end + t0;
                t.start_cap_vertices =
                    t.start_cap_vertices.start + v0..t.start_cap_vertices.end + v0;
                t.tris = t.tris.start + t0..t.tris.end + t0;
                let b = t.branch as usize;
                if piece_index == 0 {
                    first_tube[b] = Some(tubes.len() as u32);
                }
                let toward = match (piece_index, branches[b].attachment) {
                    (0, Attachment::Secondary { .. }) => Some(t.anchor),
                    (0, Attachment::Soma { .. }) => spliced_trunk[b],
                    (0, Attachment::Root) => None,
                    _ => Some(t.anchor),
                };
                if let Some(toward) = toward {
                    joins.push(Join {
                        tube: tubes.len() as u32,
                        toward,
                    });
                }
                tubes.push(t);
            }
        }
    }
    let somas = somas
        .into_iter()
        .map(|plan| {
            let trunks = plan
                .trunks
                .iter()
                .filter_map(|&b| first_tube[b as usize])
                .collect();
            (plan, trunks)
        })
        .collect();
    // Only the fillers that add a measurable share of the cell's volume, and
    // none where the radii cannot be in the coordinates' units: every
    // branch then sits inside a ball far wider than the cell, and its
    // fillers would cross each other millions of times (a whole-brain
    // axon whose radius column holds codes: 9.6 million pairs, 82 s).
    let plausible = crate::input::plausibility::radius_warning(&m).is_none();
    let cell: f64 = tracks
        .iter()
        .map(|t| crate::build::coverage::slices(t, 0, t.samples.len(), |_| 1.0))
        .sum();
    let worth = |gain: f64| plausible && gain >= reach.min_gain * cell;
    let substantial = |gain: f64| gain >= crate::build::filler::MIN_GAIN * cell;
    // Each branch's start filler (along the straight track for a trunk that
    // has one), then those of the segments whose contours no piece took
    // (each along its own cone).
    let segments: Vec<(u32, (u32, f64))> = segments
        .into_iter()
        .filter(|&(_, (_, gain))| worth(gain))
        .collect();
    let segment_filler = |i: usize| {
        let (b, (s, gain)) = segments[i];
        let points = &branches[b as usize].samples;
        let (p, q) = (points[s as usize] as usize, points[s as usize + 1] as usize);
        let radii = [geometry.radius[p], geometry.radius[q]];
        let edge = tracks[b as usize].edge;
        // The filler of the segment before, if any, ends in a dome around
        // this one's start.
        let flat_start = i > 0 && segments[i - 1].0 == b && segments[i - 1].1.0 + 1 == s;
        let ends = (geometry.pos[p], geometry.pos[q]);
        let track = crate::build::filler::segment_track(ends, radii, edge, params, flat_start)?;
        let n = track.samples.len();
        Some((
            b,
            (0, n, gain),
            Some(Straight {
                track,
                first: s,
                flat_start,
                flat_end: false,
            }),
        ))
    };
    // Branch, track points `from..to` and estimated gain, own track.
    type Candidate = (u32, (usize, usize, f64), Option<Straight>);
    let starts: Vec<Candidate> = filler
        .iter()
        .enumerate()
        .filter_map(|(b, f)| {
            let straight = filler_track[b].take();
            f.map(|f| (b as u32, f, straight))
        })
        .filter(|c| worth(c.1.2))
        .collect();
    let gains = || {
        starts
            .iter()
            .map(|c| c.1.2)
            .chain(segments.iter().map(|s| s.1.1))
    };
    // Together they must change the volume by a visible share: each costs
    // crossing pairs, and a cell they would change by half a percent meshes
    // twice as fast without them. Only fillers of at least `MIN_GAIN` count
    // toward that share: the finer ones are built where the larger ones
    // are, never alone (on a retinal neuron whose larger fillers came to
    // 0.13 %, 343 finer ones would triple its meshing time). The segments'
    // tracks are built only then.
    let built = gains().filter(|&g| substantial(g)).sum::<f64>()
        >= crate::build::filler::MIN_TOTAL_GAIN * cell;
    let fine_fillers = built && gains().any(|g| !substantial(g));
    let (fillers, filler_straight): (Vec<_>, Vec<_>) = if built {
        starts
            .into_iter()
            .chain((0..segments.len()).filter_map(segment_filler))
            .map(|(b, (from, to, _), straight)| ((b, from, to), straight))
            .unzip()
    } else {
        (Vec::new(), Vec::new())
    };
    let widest = tracks.iter().map(Track::widest).fold(1.0, f64::max);
    let mut needed = vec![false; tracks.len()];
    for (&(b, ..), straight) in fillers.iter().zip(&filler_straight) {
        needed[b as usize] |= straight.is_none();
    }
    let tracks = tracks
        .into_iter()
        .zip(needed)
        .map(|(t, n)| if n { t } else { Track::default() })
        .collect();
    Ok(TubeStage {
        surface,
        branches,
        tubes,
        joins,
        somas,
        stats,
        owner: Vec::new(),
        tracks,
        widest,
        fillers,
        filler_straight,
        filler_parts: u32::MAX,
        filler_of_part: Vec::new(),
        origin,
        fine_fillers,
    })
}
