//! Where each branch's tube starts, and which trunks the soma takes.
//!
//! * A **secondary** starts at its first contour clear of the round cones of
//!   every earlier branch near its branch point (see [`crate::build::coverage`]).
//! * A **soma trunk** starts at its first contour outside the soma's sphere.
//!   Its footprint (that contour projected onto the sphere) must not meet the
//!   footprint of a thicker trunk: such a trunk is not joined by the soma's
//!   triangulation but spliced like a secondary onto whatever it grows out of
//!   (the soma or the thicker trunk), from its first contour clear of both.
//! * A root branch starts at its first point.
//!
//! `None` marks a branch whose every contour lies inside what it would join:
//! it is hidden and not meshed.

use glam::DVec3;

use crate::build::coverage::ConeIndex;
use crate::build::filler::cone::{Straight, dome_leaves_sphere, straight_track};
use crate::build::filler::gain::span;
use crate::build::soma::{self, Footprint, Sphere};
use crate::kernel::round_cone::RoundCone;
use crate::params::Params;
use crate::skeleton::Skeleton;
use crate::skeleton::branch::{Attachment, Branch};
use crate::skeleton::geometry::Geometry;
use crate::skeleton::track::Track;

/// The soma of one tree, as the mesher will build it.
#[derive(Debug, Clone, PartialEq)]
pub struct SomaPlan {
    /// Its sphere (radius corrected for the point spacing).
    pub sphere: Sphere,
    /// Point spacing on the sphere.
    pub spacing: f64,
    /// The sample its vertices are labelled with.
    pub label: u32,
    /// Branches whose first contour its triangulation joins.
    pub trunks: Vec<u32>,
}

/// Where every tube starts and how it is joined.
#[derive(Debug, Clone, Default)]
pub struct Starts {
    /// Track point each branch's tube starts at (`None`: hidden).
    pub start: Vec<Option<usize>>,
    /// For trunks spliced like secondaries: the point on the soma below them.
    pub spliced_trunk: Vec<Option<DVec3>>,
    /// One plan per tree with a soma.
    pub somas: Vec<SomaPlan>,
    /// Per branch, the track points `from..to` of its filler, if it gets one
    /// ([`crate::build::filler`]), and the volume it would add, estimated.
    pub filler: Vec<Option<(usize, usize, f64)>>,
    /// Per branch, the track its filler is built from when it is not the
    /// branch's own: a trunk's first round cone, straight (`set_trunk_filler`).
    pub filler_track: Vec<Option<Straight>>,
}

/// A trunk must leave the sphere at least this steeply (cosine between its
/// direction and the sphere's normal) for the soma to take it: the bridge from
/// its footprint runs along the radii.
const MIN_TRUNK_STEEPNESS: f64 = 0.25;

/// Decides every branch's start (see the module documentation).
pub fn plan(skeleton: &Skeleton, params: &Params) -> Starts {
    let Skeleton {
        morphology: m,
        geometry,
        branches,
        tracks,
        ..
    } = skeleton;
    // Cells sized once for the whole cell; each use fills its own copy with
    // just the branches its queries may return.
    let empty = ConeIndex::empty_for(tracks);
    let mut out = Starts {
        start: vec![Some(0); branches.len()],
        spliced_trunk: vec![None; branches.len()],
        somas: Vec::new(),
        filler: vec![None; branches.len()],
        filler_track: vec![None; branches.len()],
    };
    let soma = m.soma_mask();
    for (ti, tree) in m.trees().iter().enumerate() {
        if let Some(s) = &tree.soma {
            let trunk = Trunk {
                geometry,
                params,
                empty: &empty,
            };
            plan_soma(&mut out, ti as u32, s, branches, tracks, &trunk);
        }
    }
    // A secondary is compared with the earlier branches that keep a start:
    // they are added to this index as the loop passes them, so a query never
    // wades through the cones of branches it would reject (with radius codes
    // in place of radii, every cone reaches every query, and filtering the
    // whole index per branch made the planning quadratic).
    let mut earlier = empty.clone();
    let mut added = 0;
    for (i, b) in branches.iter().enumerate() {
        let Attachment::Secondary { parent, at } = b.attachment else {
            continue;
        };
        // Starts before `i` are final: trunks were planned above, and each
        // secondary is planned at its turn.
        for j in added..i {
            if out.start[j].is_some() {
                earlier.add(j as u32, &tracks[j]);
            }
        }
        added = i;
        let t = &tracks[i];
        let tp = &tracks[parent as usize];
        let rp = tp.radii[tp.originals[at as usize]];
        // Far enough for a secondary leaving at 20° to clear a primary.
        let reach = 8.0 * (rp + t.radii.iter().take(8).copied().fold(0.0, f64::max));
        let cones = earlier.near(tracks, t.samples[0].pos, reach);
        out.start[i] = crate::build::coverage::first_outside(t, &cones);
        if !soma[b.samples[0] as usize] {
            // The branch point's own sphere is part of the cell's volume too.
            let mut around = cones;
            let p = tp.samples[tp.originals[at as usize]].pos;
            around.push(RoundCone::sphere(p, rp));
            out.filler[i] = span(t, out.start[i], &around);
        }
    }
    out
}

/// What planning a soma's trunks reads besides the tracks.
struct Trunk<'a> {
    geometry: &'a Geometry,
    params: &'a Params,
    /// An index with no cones, its cells sized for the whole cell.
    empty: &'a ConeIndex,
}

fn plan_soma(
    out: &mut Starts,
    tree: u32,
    s: &crate::input::morphology::Soma,
    branches: &[Branch],
    tracks: &[Track],
    with: &Trunk,
) {
    // The trunks placed so far, which a spliced trunk must clear.
    let mut placed_index = with.empty.clone();
    let center = DVec3::from_array(s.center);
    // Trunks start clear of the largest sphere the soma may be meshed with.
    let coarsest = soma::spacing(s.radius, Some(f64::INFINITY)) / s.radius;
    let outer = soma::mesh_radius(s.radius, coarsest);
    let ball = [RoundCone::sphere(center, outer)];
    let trunks: Vec<usize> = (0..branches.len())
        .filter(|&i| branches[i].attachment == Attachment::Soma { tree })
        .collect();
    let mut edges = Vec::new();
    for &i in &trunks {
        out.start[i] = crate::build::coverage::first_outside(&tracks[i], &ball);
        if let Some(k) = out.start[i] {
            let t = &tracks[i];
            edges.push(std::f64::consts::TAU * t.radii[k] / f64::from(t.counts[k]));
        }
    }
    let mean_edge = (!edges.is_empty()).then(|| edges.iter().sum::<f64>() / edges.len() as f64);
    let spacing = soma::spacing(s.radius, mean_edge);
    let sphere = Sphere {
        center,
        radius: soma::mesh_radius(s.radius, spacing / s.radius),
    };
    // Thickest first; a trunk whose footprint meets a kept one is spliced.
    let mut order: Vec<usize> = trunks
        .iter()
        .copied()
        .filter(|&i| out.start[i].is_some())
        .collect();
    let mut first_radius = vec![0.0; tracks.len()];
    for &i in &order {
        first_radius[i] = tracks[i].radii[out.start[i].unwrap_or(0)];
    }
    order.sort_by(|&a, &b| first_radius[b].total_cmp(&first_radius[a]).then(a.cmp(&b)));
    // A trunk's filler starts where its first cone leaves the sphere by
    // more than a polygon's enlargement (at most 1.9 %, a 12-gon's): before
    // the hull's tangent circle the cone's sections lie on the sphere, and a
    // filler from there would graze it all round.
    let filler_ball = RoundCone::sphere(center, 1.02 * sphere.radius);
    let mut kept: Vec<(usize, Footprint)> = Vec::new();
    for &i in &order {
        let t = &tracks[i];
        let k = out.start[i].unwrap_or(0);
        let print = soma::footprint(&soma::footprint_loop(&sphere, &contour_points(t, k)));
        let steep = t.samples[k].tangent.dot(print.dir) >= MIN_TRUNK_STEEPNESS;
        // Caps closer than this leave no room for a point between their loops.
        let margin = 0.25 * spacing / s.radius;
        if steep
            && kept
                .iter()
                .all(|(_, f)| !soma::footprints_meet(f, &print, margin))
        {
            kept.push((i, print));
            set_trunk_filler(out, i, &branches[i], t, with, &[filler_ball]);
        } else {
            // Clear of the sphere and of every trunk placed so far.
            let reach =
                8.0 * (first_radius[i] + t.radii.iter().take(8).copied().fold(0.0, f64::max));
            let mut cones = placed_index.near(tracks, t.samples[k].pos, reach + s.radius);
            cones.push(ball[0]);
            out.start[i] = crate::build::coverage::first_outside_from(t, k, &cones);
            out.spliced_trunk[i] = Some(center + sphere.radius * print.dir);
            cones.pop();
            cones.push(filler_ball);
            set_trunk_filler(out, i, &branches[i], t, with, &cones);
        }
        placed_index.add(i as u32, t);
    }
    kept.sort_by_key(|(i, _)| *i);
    out.somas.push(SomaPlan {
        sphere,
        spacing,
        label: s.samples[0],
        trunks: kept.iter().map(|(i, _)| *i as u32).collect(),
    });
}

/// A trunk filler's last contour, inside the tube, is drawn in to this
/// fraction of its radius. Its last band then meets the tube's at an angle
/// instead of along it; drawn in further it leaves more of the cone before
/// the tube's start uncovered (0.8 lost 1 % of a motoneuron's volume, 0.95
/// 0.4 %, with no union failing on the 48 files either way).
const TUCK: f64 = 0.95;

/// A trunk's filler: its first round cone, from the soma sample to its first
/// neurite sample, as a straight track from where it leaves `cones` (the
/// sphere, and for a spliced trunk the trunks placed before it) up to the
/// trunk's tube start (or the sample, if the tube starts beyond it).
///
/// Where a trunk flares out of the soma (a soma of radius 9 and a first
/// sample of radius 0.3 thirty units out) that cone is a large share of the
/// union of round cones, and neither the soma's radial bridge nor a spliced
/// trunk's covers it: the bridge meets the sphere under the start contour,
/// while the cone's flank is tangent to the sphere much farther out. Why not
/// the trunk's own contours there: the tube's tangents follow the curve at
/// the scale of its radius, and near the soma that radius is the soma's, so
/// its first discs tilt with the bends beyond the first sample and stand out
/// of the union (a filler from them added 9 % to a motoneuron's volume).
fn set_trunk_filler(
    out: &mut Starts,
    i: usize,
    b: &Branch,
    t: &Track,
    with: &Trunk,
    cones: &[RoundCone],
) {
    let &[s0, s1, ..] = b.samples.as_slice() else {
        return;
    };
    let (g, (s0, s1)) = (with.geometry, (s0 as usize, s1 as usize));
    let (p0, p1) = (g.pos[s0], g.pos[s1]);
    let length = p0.distance(p1);
    if length <= 0.0 {
        return;
    }
    let axis = (p1 - p0) / length;
    let radii = [g.radius[s0], g.radius[s1]];
    // Sampled like the trunk itself.
    let Some(mut straight) = straight_track(p0, p1, radii, t.edge, with.params) else {
        return;
    };
    // Up to its first contour half a step or more beyond the tube's start,
    // so that its end lies in the tube, drawn in there ([`TUCK`]) and capped
    // flat (`build::build_fillers`). Ending at full radius, its last bands
    // would run along the tube's own first bands, the same cone drawn by
    // polygons out of phase: hundreds of grazing crossings, each a round of
    // nudges for the overlap pass. A dome
    // there would also bulge out of a cone that narrows faster than a
    // sphere. Its start dome lies in the soma sample's sphere, which the
    // union holds.
    let reach = out.start[i].map_or(length, |k| (t.samples[k].pos - p0).dot(axis));
    let x = |k: usize| (straight.samples[k].pos - p0).dot(axis);
    let n = straight.samples.len();
    // A tube that starts at the soma sample itself or behind it (the
    // sample's sphere wider than the soma's, as where a 3-point soma is not
    // recognised) starts flat there, and its splice may move that start on:
    // the filler then takes the whole cone, its start dome holding the half
    // of the sample's sphere behind the tube.
    let mut last = if reach <= 0.0 {
        n - 1
    } else {
        (0..n).find(|&k| x(k) >= reach).unwrap_or(n - 1)
    };
    if last > 0 && last + 1 < n && x(last) < reach + 0.5 * (x(last) - x(last - 1)) {
        last += 1;
    }
    if x(last) > reach {
        straight.radii[last] *= TUCK;
    }
    let end = last + 1;
    if let Some(span) = span(&straight, Some(end), cones) {
        let flat_end = dome_leaves_sphere(&straight, radii[1]);
        out.filler[i] = Some(span);
        out.filler_track[i] = Some(Straight {
            track: straight,
            first: 0,
            flat_start: false,
            flat_end,
        });
    }
}

/// The contour vertices of track point `k`, as the tube will place them.
fn contour_points(t: &Track, k: usize) -> Vec<DVec3> {
    let s = &t.samples[k];
    let u = t.frames[k];
    crate::skeleton::contour::ring(s.pos, s.tangent, u, t.radii[k], t.counts[k]).collect()
}
