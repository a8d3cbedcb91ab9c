//! The retry policy: a construction whose fillers leave crossings the
//! overlap pass cannot cut is meshed again without the filler pieces in
//! them, up to [`MAX_FILLER_RETRIES`] times, and without any fillers at
//! last, rather than left crossing itself.

use crate::build::{Construction, FIRST_REACH, FillerParts, SAFE_REACH, construct};
use crate::error::Result;
use crate::input::morphology::Morphology;
use crate::mesh::Mesh;
use crate::overlap::{self, Resolved};
use crate::params::Params;
use crate::skeleton::track::SAFE_SWEEP_CAP;

/// Stage 6 on `stage`, constructed from `morphology` by [`construct`]: the
/// mesh with its overlaps resolved and fillers united. Tubes widened to
/// [`crate::skeleton::track::SWEEP_CAP`] and the smaller fillers
/// [`FIRST_REACH`] builds can crowd the fillers on a thick trunk past what
/// the overlap pass cuts; where the
/// first union leaves crossings the cell is built again at [`SAFE_REACH`]
/// and finished there, retries and all. Only such cells pay
/// for the second construction, and only if a contour was widened past the
/// safe cap or a filler below [`crate::build::filler::gain::MIN_GAIN`] was built:
/// otherwise the second would be the first again, and the retries go on
/// from the first.
///
/// # Errors
/// [`crate::Error::InvalidParam`] for a bad parameter.
pub fn unite(morphology: &Morphology, params: &Params, stage: Construction) -> Result<Mesh> {
    // Where no contour was widened past the safe cap, building again at it
    // would give the same stage, and the same first try: the retries go on
    // from this one.
    let widened_past_safe = stage.widest > SAFE_SWEEP_CAP * (1.0 + 1e-9);
    let fine_fillers = stage.fillers.fine;
    let first = first_try(stage);
    if let FirstTry::Clean(mesh) = first {
        return Ok(mesh);
    }
    if !widened_past_safe && !fine_fillers {
        return retry(first, || construct(morphology, params, FIRST_REACH));
    }
    let safe = || construct(morphology, params, SAFE_REACH);
    finish(safe()?, safe)
}

/// Stage 6 on a constructed stage: the mesh, with the overlaps resolved and
/// the fillers united with the rest (or dropped; see [`crate::build::filler`]).
/// `rebuild` constructs the same stage again; it is called only when the
/// fillers leave crossings the pass cannot cut, so the first try works on the
/// mesh itself rather than on a copy kept for that rare case.
///
/// # Errors
/// What `rebuild` returns.
fn finish(stage: Construction, rebuild: impl FnOnce() -> Result<Construction>) -> Result<Mesh> {
    retry(first_try(stage), rebuild)
}

/// [`finish`] after its first try: the mesh it made, or the retries that
/// leave out the fillers in the crossings it left, on the stage `rebuild`
/// constructs again.
fn retry(first: FirstTry, rebuild: impl FnOnce() -> Result<Construction>) -> Result<Mesh> {
    let (stuck, fillers) = match first {
        FirstTry::Clean(mesh) | FirstTry::Crossed(mesh) => return Ok(mesh),
        FirstTry::Stuck { stuck, fillers } => (stuck, fillers),
    };
    // The fillers add crossings; should the pass fail to cut some, the cell
    // is meshed again without the filler pieces in them (and again, up to
    // `MAX_FILLER_RETRIES` times, without those in the crossings each try
    // leaves), and should that fail too, as the paper builds it, without
    // fillers, rather than left crossing itself.
    // Construction is deterministic: the rebuilt mesh numbers its faces and
    // parts as the first did, so `stuck` and `fillers` still name them.
    let (mesh, face_owner) = rebuild()?.into_mesh();
    let mut stuck = stuck;
    for attempt in 0..MAX_FILLER_RETRIES {
        if stuck.is_empty()
            || (attempt > 0 && stuck.len() as f64 > MAX_STUCK_SHARE * fillers.of_part.len() as f64)
        {
            break;
        }
        let (fewer, resolved) = unite_without(&fillers, mesh.clone(), face_owner.clone(), |o| {
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
    Ok(unite_without(&fillers, mesh, face_owner, |o| fillers.has(o)).0)
}

/// How the first union of a constructed stage went.
enum FirstTry {
    /// Nothing is left crossing.
    Clean(Mesh),
    /// A stage without fillers whose overlaps the pass left crossing: there
    /// is nothing to leave out and try again.
    Crossed(Mesh),
    /// The fillers' union left crossings: the filler parts in them, sorted,
    /// and the stage's filler parts.
    Stuck {
        stuck: Vec<u32>,
        fillers: FillerParts,
    },
}

/// The stage's mesh with its overlaps resolved and all its fillers united.
fn first_try(mut stage: Construction) -> FirstTry {
    let fillers = std::mem::take(&mut stage.fillers);
    let (mesh, face_owner) = stage.into_mesh();
    let has_fillers = face_owner.last().is_some_and(|&o| fillers.has(o));
    if !has_fillers {
        let mut mesh = mesh;
        resolve_overlaps(&mut mesh, face_owner);
        if mesh.stats.overlap_pairs > 0 && mesh.stats.overlap_pairs_left == 0 {
            super::shells::drop_shells(&mut mesh, |_| false);
        }
        return if mesh.stats.overlap_pairs_left == 0 {
            FirstTry::Clean(mesh)
        } else {
            FirstTry::Crossed(mesh)
        };
    }
    let (united, resolved) = unite_without(&fillers, mesh, face_owner, |_| false);
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
    FirstTry::Stuck { stuck, fillers }
}

/// How many times the mesher unites the fillers again, each time also
/// without those in the crossings the last try left, before it gives all of
/// them up. Which contacts the pass fails to cut shifts from try to try, so
/// a few tries keep most fillers where a single one would give them all up.
const MAX_FILLER_RETRIES: usize = 3;

/// After its first retry, the mesher unites the fillers again only while
/// those left out are at most this share of their pieces. More means the
/// contacts are degenerate all over (a trace rounded to a voxel grid), and
/// leaving out the pieces in the crossings each try leaves does not get
/// through them: every retry costs a whole union, to end without fillers
/// anyway.
///
/// The first retry is made whatever the share: fillers crowding one thick
/// trunk can leave one cluster of crossings uncut, and all of them with it;
/// united without that cluster, the cell keeps the rest of its fillers.
const MAX_STUCK_SHARE: f64 = 0.125;

/// `mesh` (whose face `f` is of part `owner[f]`) without the faces
/// of the filler parts `dropped` accepts, its overlaps resolved, and what
/// the pass told. Where nothing crosses, the fillers lie inside the rest
/// and are removed; where the union was built, so are the shells
/// [`super::shells::drop_shells`] names. `stats.fillers` counts the fillers kept.
fn unite_without(
    fillers: &FillerParts,
    mut out: Mesh,
    mut owner: Vec<u32>,
    dropped: impl Fn(u32) -> bool,
) -> (Mesh, Resolved) {
    let gone = |o: u32| fillers.has(o) && dropped(o);
    if owner.iter().any(|&o| gone(o)) {
        out.retain_faces(|f| !gone(owner[f]));
        owner.retain(|&o| !gone(o));
    }
    let resolved = overlap::resolve(&mut out, owner);
    out.stats.overlap_pairs = resolved.outcome.pairs;
    out.stats.overlap_pairs_left = resolved.outcome.pairs_left;
    let mut kept: Vec<u32> = (0..fillers.of_part.len() as u32)
        .filter(|&k| !dropped(fillers.first + k))
        .map(|k| fillers.of_part[k as usize])
        .collect();
    if resolved.outcome.pairs == 0 {
        // The pass changed nothing: the owners it hands back are those
        // it was given.
        out.retain_faces(|f| !fillers.has(resolved.owner[f]));
        kept.clear();
    } else if resolved.outcome.pairs_left == 0 && !kept.is_empty() {
        super::shells::drop_shells(&mut out, |f| fillers.has(resolved.owner[f]));
    }
    kept.sort_unstable();
    kept.dedup();
    out.stats.fillers = kept.len() as u32;
    (out, resolved)
}

/// Stage 6 on a mesh without fillers: where its parts cross each other,
/// the boundary of their union replaces them ([`crate::overlap`]); counted
/// in the stats.
fn resolve_overlaps(mesh: &mut Mesh, face_owner: Vec<u32>) {
    let outcome = overlap::resolve(mesh, face_owner).outcome;
    mesh.stats.overlap_pairs = outcome.pairs;
    mesh.stats.overlap_pairs_left = outcome.pairs_left;
}
