//! How large a mesh will be, known before any of it is built.
//!
//! Formula (1) spaces contours by the branch's radius, so the work follows
//! the ratio of segment lengths to radii, not the cell's shape: a file whose
//! radii are a millionth of its segments (radii in the wrong unit, a radius
//! column of zeros floored to almost nothing, one coordinate of 1e8) asks
//! for hundreds of millions of contours. [`estimate`] counts, per segment
//! of the skeleton, the contours formula (1) puts on it and the vertices
//! formula (3) gives them, from the radii as the mesher will use them (scaled
//! and raised to the floor of [`crate::skeleton::geometry`]), in time linear
//! in the samples. [`check`] refuses a cell whose estimate passes
//! [`Params::face_limit`] with the line of the segment that asks for most,
//! before anything is allocated for it, and, first, values no cell has
//! ([`check_values`]: a coordinate of 1e30, one sample a hundred times
//! farther out than the rest).
//!
//! The estimate is of the triangles before straight stretches are thinned
//! ([`crate::skeleton::thinning`]) and fillers are added: on the 48 corpus
//! files it is 0.6 to 3.5 times the triangles the mesh ends with (median
//! 1.6; `examples/face_estimate`), but for the two cells meshed whole as a
//! blob, and takes under 4 ms.

use crate::error::{Error, Result};
use crate::input::morphology::{Morphology, NO_PARENT};
use crate::params::Params;
use crate::skeleton::contour::vertex_count;
use crate::skeleton::geometry::{longest_side, radius_floor};
use crate::skeleton::spline::MAX_INSERTED_PER_SEGMENT;

/// What [`estimate`] finds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// Triangles before thinning, summed over the segments.
    pub faces: f64,
    /// The sample whose segment (to its parent) asks for most triangles,
    /// `NO_PARENT` for a cell without segments.
    pub largest: u32,
    /// That segment's triangles.
    pub largest_faces: f64,
    /// Its length over its mean radius (after the floor).
    pub length_over_radius: f64,
}

/// The triangles `params` would give `morphology` before thinning, and the
/// segment that asks for most.
pub fn estimate(morphology: &Morphology, params: &Params) -> Estimate {
    let scale = params.scale;
    let pos = morphology.positions();
    let floor = radius_floor(morphology, params);
    let radius = |i: usize| (morphology.radii()[i] * scale).max(floor);
    let mut out = Estimate {
        faces: 0.0,
        largest: NO_PARENT,
        largest_faces: 0.0,
        length_over_radius: 0.0,
    };
    for (c, &p) in morphology.parents().iter().enumerate() {
        if p == NO_PARENT || (morphology.is_soma(c as u32) && morphology.is_soma(p)) {
            continue;
        }
        let p = p as usize;
        let d = (0..3)
            .map(|k| (pos[c][k] - pos[p][k]) * scale)
            .map(|x| x * x)
            .sum::<f64>()
            .sqrt();
        let (rc, rp) = (radius(c), radius(p));
        let edge = 0.5 * (rc + rp) / params.resolution;
        let ratio = d / edge;
        let contours =
            (ratio.floor().min(MAX_INSERTED_PER_SEGMENT as f64)) + f64::from(params.k1) + 1.0;
        let vertices = vertex_count(rc.max(rp), edge, params.min_vertices, params.max_vertices);
        let faces = 2.0 * f64::from(vertices) * contours;
        out.faces += faces;
        if faces > out.largest_faces {
            out.largest = c as u32;
            out.largest_faces = faces;
            out.length_over_radius = ratio * params.resolution;
        }
    }
    out
}

/// Refuses `morphology` when [`check_values`] does, or when its
/// [`estimate`] passes `params.face_limit` (0: no limit), naming the segment
/// that asks for most triangles.
///
/// # Errors
/// [`Error::Swc`] at the line of the sample at fault, with the estimate,
/// the limit and what would reduce it.
pub fn check(morphology: &Morphology, params: &Params) -> Result<Estimate> {
    check_values(morphology, params.scale)?;
    check_radius_unit(morphology, params)?;
    let e = estimate(morphology, params);
    let limit = f64::from(params.face_limit);
    if params.face_limit == 0 || e.faces <= limit || e.largest == NO_PARENT {
        return Ok(e);
    }
    let s = e.largest as usize;
    let lines = morphology.lines();
    let cause = if e.length_over_radius > 1000.0 {
        format!(
            "its segment to its parent (line {}) is {:.3e} times its radius long \
             (radii in another unit than the coordinates, or an outlying coordinate?)",
            lines[morphology.parents()[s] as usize],
            e.length_over_radius
        )
    } else {
        format!(
            "its segment to its parent (line {}) alone asks for {:.3e}",
            lines[morphology.parents()[s] as usize],
            e.largest_faces
        )
    };
    Err(Error::swc(
        morphology.name(),
        lines[s] as usize,
        format!(
            "the mesh would have about {:.3e} triangles, more than face_limit ({}): {cause}; \
             raise --min-radius (radius floor, output units), lower --resolution, \
             or raise --face-limit (0: no limit)",
            e.faces, params.face_limit
        ),
    ))
}

/// Coordinates and radii, after the scale, are at most this large in
/// magnitude: the output is f32, and the programs that read meshes square
/// distances in f32, which overflows beyond about 1e19.
pub const LARGEST_VALUE: f64 = 1e15;

/// A sample lies this many times farther from the cell's centre than 99 %
/// of the samples (and than a hundred median radii) only by an error in
/// its coordinates: on the 48 corpus files the farthest sample is at most
/// 1.41 times as far. Meshed, two samples at 1e8 in a cell of 2e5 nm would
/// raise every radius to a floor ten times too thick, into tubes that
/// swallow each other.
pub const OUTLIER_FACTOR: f64 = 100.0;

/// Most children of one branch point off the soma. Where children leave one
/// point of a neurite, every pair of them crosses near it, and the overlap
/// pass that unites them grows much faster than their number (on a small
/// cell, optimized debug build: 10 children 0.5 s, 20 8.5 s, 50 329 s); real cells have at most about 10 (the corpus's
/// largest has 10), and a soma takes hundreds (it is built as a sphere with
/// trunks).
pub const MAX_CHILDREN: usize = 24;

/// Refuses values that no cell has: a coordinate or radius beyond
/// [`LARGEST_VALUE`], a branch point off the soma with more than
/// [`MAX_CHILDREN`] children, and a sample [`OUTLIER_FACTOR`] times farther
/// from the cell's centre than 99 % of the samples. Meshed, the first
/// overflows the output, the second runs for minutes, and the third turns
/// the relative radius floor of [`crate::skeleton::geometry`] into a blob
/// the size of the outlier.
///
/// # Errors
/// [`Error::Swc`] at the line of the first such sample.
pub fn check_values(morphology: &Morphology, scale: f64) -> Result<()> {
    let (pos, radii, lines) = (
        morphology.positions(),
        morphology.radii(),
        morphology.lines(),
    );
    let at = |i: usize, reason: String| Error::swc(morphology.name(), lines[i] as usize, reason);
    for (i, (p, &r)) in pos.iter().zip(radii).enumerate() {
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            if (p[k] * scale).abs() > LARGEST_VALUE {
                return Err(at(
                    i,
                    format!(
                        "{axis} = {:.3e} is beyond ±{LARGEST_VALUE:.0e} (after the scale), \
                         more than a mesh's f32 coordinates can be computed with",
                        p[k]
                    ),
                ));
            }
        }
        if r * scale > LARGEST_VALUE {
            return Err(at(
                i,
                format!(
                    "radius {r:.3e} is beyond {LARGEST_VALUE:.0e} (after the scale), \
                     more than a mesh's f32 coordinates can be computed with"
                ),
            ));
        }
    }
    if let Some(i) = (0..pos.len()).find(|&i| {
        !morphology.is_soma(i as u32) && morphology.children(i as u32).len() > MAX_CHILDREN
    }) {
        return Err(at(
            i,
            format!(
                "the sample has {} children: a branch point off the soma with more than \
                 {MAX_CHILDREN} is not meshed (the union of its children's crossings grows \
                 much faster than their number)",
                morphology.children(i as u32).len()
            ),
        ));
    }
    let n = pos.len();
    if n < 20 {
        return Ok(());
    }
    let median = |mut v: Vec<f64>| {
        let m = v.len() / 2;
        *v.select_nth_unstable_by(m, f64::total_cmp).1
    };
    let centre: [f64; 3] = std::array::from_fn(|k| median(pos.iter().map(|p| p[k]).collect()));
    let distance = |p: &[f64; 3]| {
        (0..3)
            .map(|k| (p[k] - centre[k]).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let mut d: Vec<f64> = pos.iter().map(distance).collect();
    // The 99th percentile, and never the farthest sample itself.
    let q = ((n - 1) * 99 / 100).min(n - 2);
    let typical = *d.select_nth_unstable_by(q, f64::total_cmp).1;
    let reach = OUTLIER_FACTOR * typical.max(100.0 * median(radii.to_vec()));
    if let Some(i) = pos.iter().position(|p| distance(p) > reach) {
        return Err(at(
            i,
            format!(
                "the sample lies {:.3e} from the cell's centre, more than {OUTLIER_FACTOR:.0} \
                 times as far as 99 % of its samples ({typical:.3e}): an outlying coordinate?",
                distance(&pos[i])
            ),
        ));
    }
    Ok(())
}

/// Most radii below this fraction of the cell's size (the longest side of
/// its box) say that radii and coordinates are in different units: the
/// radius floor ([`crate::skeleton::geometry::RELATIVE_RADIUS_FLOOR`], ten
/// times this) would raise them all, by up to millions of times, into tubes
/// that swallow each other. Real cells' radii are 1e-5 of their size and
/// more (a 10 mm axon of 0.1 um).
pub const THIN_RADIUS: f64 = 1e-6;

/// Refuses a cell most of whose radii are below [`THIN_RADIUS`] of its size,
/// unless `params.min_radius` raises them above it (the user's own floor).
///
/// # Errors
/// [`Error::Swc`] at the line of the first such radius.
pub fn check_radius_unit(morphology: &Morphology, params: &Params) -> Result<()> {
    let side = longest_side(morphology, params.scale);
    let thin = THIN_RADIUS * side;
    if params.min_radius >= thin {
        return Ok(());
    }
    let radii = morphology.radii();
    let is_thin = |r: f64| r * params.scale < thin;
    let count = radii.iter().filter(|&&r| is_thin(r)).count();
    if 2 * count <= radii.len() {
        return Ok(());
    }
    let first = radii.iter().position(|&r| is_thin(r)).unwrap_or(0);
    Err(Error::swc(
        morphology.name(),
        morphology.lines()[first] as usize,
        format!(
            "radius {:.3e} is under {THIN_RADIUS:.0e} of the cell's size ({:.3e}), as are {count} \
             of its {} radii: radii and coordinates in different units? (--scale scales both; \
             --min-radius sets a radius floor of your own)",
            radii[first],
            side / params.scale,
            radii.len()
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn morph(text: &str) -> Morphology {
        let file = crate::input::swc::SwcFile::parse(text.as_bytes(), "t.swc").expect("valid");
        Morphology::from_file(file).expect("valid")
    }

    /// A soma and a straight dendrite of `n` unit steps of radius `r`.
    fn dendrite(n: usize, r: f64) -> String {
        let mut text = String::from("1 1 0 0 0 3 -1\n");
        for i in 2..=n + 1 {
            text += &format!("{i} 3 {} 0 0 {r} {}\n", 2 + i, i - 1);
        }
        text
    }

    fn reason(m: &Morphology, params: &Params) -> (usize, String) {
        match check(m, params) {
            Err(Error::Swc(e)) => (e.line, e.reason),
            other => panic!("expected a refusal, got {other:?}"),
        }
    }

    #[test]
    fn the_estimate_follows_formulas_one_and_three() {
        // 40 segments of length 1 at radius 0.5: floor(1 / 0.5) + k1 + 1 = 4
        // contours of 12 vertices each, 2 triangles per vertex and contour.
        let m = morph(&dendrite(41, 0.5));
        let e = estimate(&m, &Params::default());
        assert!((e.faces - 40.0 * 4.0 * 12.0 * 2.0).abs() < 1000.0, "{e:?}");
        assert!(check(&m, &Params::default()).is_ok());
    }

    #[test]
    fn a_cell_past_the_limit_is_refused_at_its_largest_segment() {
        let mut text = dendrite(30, 0.5);
        text += "32 3 1000 0 0 0.5 31\n";
        let m = morph(&text);
        let params = Params::default().with_face_limit(10_000);
        let (line, why) = reason(&m, &params);
        assert_eq!(line, 32);
        assert!(why.contains("more than face_limit (10000)"), "{why}");
        // No limit: accepted.
        assert!(check(&m, &params.with_face_limit(0)).is_ok());
    }

    #[test]
    fn values_no_cell_has_are_refused_at_their_line() {
        let mut text = dendrite(30, 0.5);
        text += "32 3 1e30 0 0 0.5 31\n";
        let (line, why) = reason(&morph(&text), &Params::default());
        assert_eq!(line, 32);
        assert!(why.contains("beyond"), "{why}");
        let mut text = dendrite(30, 0.5);
        text += "32 3 0 1e8 0 0.5 31\n";
        let (line, why) = reason(&morph(&text), &Params::default());
        assert_eq!(line, 32);
        assert!(why.contains("outlying coordinate"), "{why}");
        // A long but plausible segment is no outlier.
        let mut text = dendrite(30, 0.5);
        text += "32 3 0 300 0 0.5 31\n";
        assert!(check(&morph(&text), &Params::default()).is_ok());
    }

    #[test]
    fn a_branch_point_with_too_many_children_is_refused() {
        let mut text = dendrite(5, 0.5);
        for k in 0..=MAX_CHILDREN {
            let a = k as f64;
            text += &format!(
                "{} 3 7 {} {} 0.3 6\n",
                10 + k,
                10.0 * a.cos(),
                10.0 * a.sin()
            );
        }
        let (line, why) = reason(&morph(&text), &Params::default());
        assert_eq!(line, 6);
        assert!(
            why.contains(&format!("{} children", MAX_CHILDREN + 1)),
            "{why}"
        );
    }

    #[test]
    fn radii_in_another_unit_than_the_coordinates_are_refused() {
        // Coordinates a million times too large: radii 1e-6 of the size and less.
        let scaled: String = dendrite(40, 0.5)
            .lines()
            .map(|l| {
                let f: Vec<&str> = l.split(' ').collect();
                let c = |k: usize| f[k].parse::<f64>().expect("number") * 1e6;
                format!(
                    "{} {} {} {} {} {} {}\n",
                    f[0],
                    f[1],
                    c(2),
                    c(3),
                    c(4),
                    f[5],
                    f[6]
                )
            })
            .collect();
        let m = morph(&scaled);
        let (line, why) = reason(&m, &Params::default());
        assert_eq!(line, 1, "the soma's radius is the first thin one");
        assert!(why.contains("different units"), "{why}");
        // A floor of the user's own takes charge of the radii.
        assert!(check(&m, &Params::default().with_min_radius(100.0)).is_ok());
        // A few thin radii in a plausible cell are only floored.
        let mut text = dendrite(40, 0.5);
        text += "42 3 50 0 0 1e-9 41\n";
        assert!(check(&morph(&text), &Params::default()).is_ok());
    }
}
