//! The morphology's round cones ([`RoundCone`]): the shape its mesh
//! stands for, as the star-hull mesher and the union's measures read it.

use glam::DVec3;

use super::{Morphology, NO_PARENT};
use crate::kernel::round_cone::RoundCone;

impl Morphology {
    /// The primitives of a morphology: one sphere per soma, one round cone per
    /// segment not between two soma samples (a lone root is a sphere).
    pub fn round_cones(&self) -> Vec<RoundCone> {
        self.labelled_round_cones().map(|(c, _)| c).collect()
    }

    /// [`Morphology::round_cones`] one at a time, each with the sample it stands
    /// for: a soma's first sample, else the child end of the segment (or the
    /// lone root). Nothing is allocated beyond the soma mask.
    pub fn labelled_round_cones(&self) -> impl Iterator<Item = (RoundCone, u32)> + '_ {
        let m = self;
        let (pos, r, parents) = (m.positions(), m.radii(), m.parents());
        let soma = m.soma_mask();
        let v = |i: usize| DVec3::from_array(pos[i]);
        let somas = m.trees().iter().filter_map(|t| t.soma.as_ref()).map(|s| {
            (
                RoundCone::sphere(DVec3::from_array(s.center), s.radius),
                s.samples.first().copied().unwrap_or(0),
            )
        });
        let segments = (0..m.len()).filter_map(move |i| {
            let p = parents[i];
            let cone = if p == NO_PARENT {
                (!soma[i]).then(|| RoundCone::sphere(v(i), r[i]))
            } else {
                (!(soma[i] && soma[p as usize])).then(|| RoundCone {
                    a: v(p as usize),
                    ra: r[p as usize],
                    b: v(i),
                    rb: r[i],
                })
            };
            cone.map(|c| (c, i as u32))
        });
        somas.chain(segments)
    }
}
