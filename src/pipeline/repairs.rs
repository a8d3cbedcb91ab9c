//! Every change the mesher makes to the geometry a file gives, said in words.
//!
//! Cleaning ([`crate::Morphology`]) merges duplicate points and fills missing
//! radii; the frame ([`crate::skeleton::geometry`]) raises radii to a floor
//! that keeps the f32 output's contours distinct. Each changes the surface
//! against the union of the radii as written, so each is said where the
//! user looks: `neuromesh mesh` and `batch` print these lines as warnings on
//! stderr, Python gives them as `UserWarning`s, and `info` counts them.

use crate::input::morphology::Morphology;
use crate::mesh::BuildStats;
use crate::params::Params;
use crate::skeleton::geometry::radius_floor;

/// The radii `params` raises to its floor: how many, the floor, and the
/// largest factor by which one grows.
pub fn raised_radii(morphology: &Morphology, params: &Params) -> (usize, f64, f64) {
    let floor = radius_floor(morphology, params);
    let (mut count, mut factor) = (0usize, 1.0f64);
    for &r in morphology.radii() {
        let r = r * params.scale;
        if r < floor {
            count += 1;
            factor = factor.max(floor / r);
        }
    }
    (count, floor, factor)
}

/// Counts every change to `morphology`'s geometry into a mesh's `stats`.
pub fn count(morphology: &Morphology, params: &Params, stats: &mut BuildStats) {
    let c = morphology.cleaning();
    stats.samples_merged = c.duplicates_merged + c.copies_merged;
    stats.radii_filled = c.radii_from_neighbours + c.radii_from_default;
    stats.soma_radii_replaced = c.soma_radius_fallbacks;
    stats.cycles_broken = c.cycles_broken;
    stats.radii_raised = u32::try_from(raised_radii(morphology, params).0).unwrap_or(u32::MAX);
}

/// One line per change made to `morphology`'s geometry (empty when none),
/// each with how many samples and by how much.
pub fn repairs(morphology: &Morphology, params: &Params) -> Vec<String> {
    let c = morphology.cleaning();
    let cleaned = [
        (
            c.duplicates_merged,
            "samples at their parent's position merged into it",
        ),
        (
            c.cycles_broken,
            "cycles of parent links broken (each cycle's first sample in the file made a root; \
             --strict refuses them)",
        ),
        (
            c.copies_merged,
            "samples that repeat another (same place, type and parent, or both roots) merged into it",
        ),
        (
            c.radii_from_neighbours,
            "zero, negative or missing radii took the nearest valid radius",
        ),
        (
            c.radii_from_default,
            "radii set to a quarter of the median segment length (no valid radius in their tree)",
        ),
        (
            c.soma_radius_fallbacks,
            "soma radii (missing, or a thousand times thinner than a neighbour) set to 1.5 times \
             the widest neighbour's",
        ),
    ];
    let mut out: Vec<String> = cleaned
        .iter()
        .filter(|(n, _)| *n > 0)
        .map(|(n, what)| format!("{n} {what}"))
        .collect();
    let (count, floor, factor) = raised_radii(morphology, params);
    if count > 0 {
        out.push(format!(
            "{count} radii raised to the floor {floor:.4e} (output units; the larger of \
             --min-radius and 1e-5 of the longest side of the cell's box, which keeps the f32 output's contours \
             distinct), by up to {factor:.3} times"
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn morph(text: &str) -> Morphology {
        let file = crate::input::swc::SwcFile::parse(text.as_bytes(), "t.swc").expect("valid");
        Morphology::from_file(file).expect("valid")
    }

    #[test]
    fn a_clean_file_has_no_repairs() {
        let m = morph("1 1 0 0 0 5 -1\n2 3 10 0 0 1 1\n3 3 20 0 0 1 2\n");
        assert!(repairs(&m, &Params::default()).is_empty());
    }

    #[test]
    fn every_repair_is_said_with_its_count() {
        // A zero radius, a duplicate point, and a radius far below the floor
        // of a cell 100,000 long.
        let m = morph("1 1 0 0 0 5 -1\n2 3 10 0 0 0 1\n3 3 10 0 0 2 2\n4 3 100000 0 0 0.001 3\n");
        let said = repairs(&m, &Params::default()).join("\n");
        assert!(
            said.contains("1 samples at their parent's position"),
            "{said}"
        );
        assert!(said.contains("radii raised to the floor"), "{said}");
        let (count, floor, factor) = raised_radii(&m, &Params::default());
        assert_eq!(count, 1);
        // 1e-5 of the box's longest side: from the soma's 5 before the
        // origin to 100,000 and the last radius.
        assert!((floor - 1.000_050_01).abs() < 1e-9, "{floor}");
        assert!((factor - floor / 0.001).abs() < 1e-6, "{factor}");
        // A floor of the user's own, far above, counts every radius.
        let p = Params::default().with_min_radius(10.0);
        assert_eq!(raised_radii(&m, &p).0, m.len());
    }

    #[test]
    fn the_floor_does_not_depend_on_where_the_cell_lies() {
        let line = |x0: f64| {
            let text: String = (0..50)
                .map(|i| {
                    let parent = if i == 0 { -1 } else { i };
                    format!(
                        "{} 3 {} 7 0 0.001 {parent}\n",
                        i + 1,
                        x0 + 2000.0 * i as f64
                    )
                })
                .collect();
            raised_radii(&morph(&text), &Params::default())
        };
        let here = line(0.0);
        assert_eq!(here.0, 50);
        for x0 in [-49_000.0, 3.0e5, 7.7e7] {
            let there = line(x0);
            assert_eq!(there.0, here.0);
            assert!(
                (there.1 - here.1).abs() <= 1e-12 * here.1,
                "{x0}: {there:?} {here:?}"
            );
        }
    }
}
