//! Surface and volume of a cell as the skeleton states them, to set next to a
//! mesh's own (the paper's Table 1 compares them the same way).
//!
//! * **NeuroMorpho.Org style** (L-Measure's Soma Surface, Total Surface and
//!   Total Volume): the soma is a sphere of its NeuroM radius; every neurite
//!   compartment (a sample and the segment to its parent) is a cylinder of the
//!   sample's radius, without end discs. Overlaps are counted twice.
//! * **Union of round cones** ([`crate::measure::union`]): the exact union of the
//!   segments' round cones with the soma as one sphere, the reference a
//!   watertight membrane mesh should match.

use std::f64::consts::PI;

use crate::input::morphology::{Morphology, NO_PARENT};
use crate::measure::union::UnionMeasures;

/// A cell's skeleton measures.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SkeletonMeasures {
    /// Soma surface, `4πr²` summed over the trees' somas.
    pub soma_surface: f64,
    /// Soma surface plus every compartment's cylinder side.
    pub total_surface: f64,
    /// Soma volume plus every compartment's cylinder.
    pub total_volume: f64,
    /// Area and volume of the union of round cones, when asked for.
    pub union: Option<UnionMeasures>,
}

impl SkeletonMeasures {
    /// All measures of `m`, the union included (seeded Monte Carlo: a few
    /// hundred milliseconds for ordinary cells, but quadratic where thousands
    /// of round cones overlap each other, as with radii given in codes).
    pub fn with_union(m: &Morphology) -> SkeletonMeasures {
        SkeletonMeasures {
            union: Some(crate::measure::union::measure_morphology(m)),
            ..SkeletonMeasures::of(m)
        }
    }

    /// The NeuroMorpho.Org-style measures of `m` (cheap), without the union.
    pub fn of(m: &Morphology) -> SkeletonMeasures {
        let (pos, r, parents) = (m.positions(), m.radii(), m.parents());
        let soma = m.soma_mask();
        let (mut soma_surface, mut soma_volume) = (0.0, 0.0);
        for s in m.trees().iter().filter_map(|t| t.soma.as_ref()) {
            soma_surface += 4.0 * PI * s.radius * s.radius;
            soma_volume += 4.0 / 3.0 * PI * s.radius.powi(3);
        }
        let (mut side, mut inside) = (0.0, 0.0);
        for i in 0..m.len() {
            let p = parents[i];
            if p == NO_PARENT || soma[i] {
                continue;
            }
            let l = crate::input::morphology::dist(pos[i], pos[p as usize]);
            side += 2.0 * PI * r[i] * l;
            inside += PI * r[i] * r[i] * l;
        }
        SkeletonMeasures {
            soma_surface,
            total_surface: soma_surface + side,
            total_volume: soma_volume + inside,
            union: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn soma_and_one_cylinder() {
        let m = Morphology::from_arrays(
            &[1, 2, 3],
            &[1, 3, 3],
            &[[0.0; 3], [0.0, 0.0, 5.0], [0.0, 0.0, 15.0]],
            &[2.0, 1.0, 1.0],
            &[-1, 1, 2],
        )
        .expect("valid");
        let s = SkeletonMeasures::with_union(&m);
        assert!((s.soma_surface - 16.0 * PI).abs() < 1e-9);
        // Compartments of length 5 and 10, radius 1.
        assert!((s.total_surface - (16.0 * PI + 2.0 * PI * 15.0)).abs() < 1e-9);
        assert!((s.total_volume - (32.0 / 3.0 * PI + PI * 15.0)).abs() < 1e-9);
        assert!(s.union.expect("asked for").volume > 32.0 / 3.0 * PI);
    }
}
