//! Raw samples → an index tree with a soma and clean radii (stage 0).
//!
//! SWC ids stop here: every later stage sees dense `u32` sample indices into the
//! arrays of [`Morphology`]. Those indices are also what a mesh vertex carries
//! (`vertex_sample`), so `morphology.ids()[vertex_sample[v]]` is the SWC id a
//! vertex was made from.
//!
//! What happens, in order:
//!
//! 1. **Ids → indices.** A parent id that does not exist is an error at the
//!    line of the sample. A cycle of parent links (automatic tracers write
//!    them) is broken: the cycle's sample that comes first in the file
//!    becomes a root, and the break is counted
//!    ([`Morphology::refuse_cycles`] makes it an error instead).
//! 2. **Duplicate consecutive points** (a sample at its parent's position, as
//!    neuTube and Simple Neurite Tracer write them) are merged into the parent: the
//!    parent keeps the larger radius and adopts the children.
//! 3. **Radii.** A radius that is zero, negative or not finite is *missing*. Each
//!    missing radius takes the radius of the nearest sample (in tree hops) whose
//!    radius is valid. A tree with no valid radius at all (some tracers write only
//!    zeros) gets `0.25 ×` its median segment length: thin enough to keep
//!    neighbouring branches apart, thick enough to mesh. A soma point with a missing
//!    radius (or one a thousand times thinner than a neighbour: a placeholder) gets
//!    `1.5 ×` the largest radius among its neighbours, so its trunks fit.
//!    The counts of all three go into [`Cleaning`].
//! 4. **Soma and roots.** The type-1 samples of a tree form its soma; when several
//!    groups exist the largest is the soma and the others are ordinary samples. A
//!    tree with a soma is re-rooted there (hemibrain files root the tree elsewhere),
//!    so every neurite leaves the soma; see [`SomaKind`] for how it is classified.
//!
//! Units are the file's own; [`Morphology::scaled`] converts (nm → µm is 0.001).

mod construct;
mod read;
mod round_cones;
mod soma_fit;

use crate::error::{Error, Result};

/// Marks "no parent" in index arrays.
pub const NO_PARENT: u32 = u32::MAX;

/// How the soma is given in the file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SomaKind {
    /// No type-1 sample: neurites only.
    None,
    /// One type-1 sample: a sphere of its radius.
    SinglePoint,
    /// NeuroMorpho's three-point soma: a centre and two points at ±r from it, along
    /// y or rotated (NeuroMorpho averages a traced contour into such points).
    ThreePoint,
    /// Several type-1 samples: a traced contour or a stack of cylinders.
    MultiPoint,
}

impl SomaKind {
    /// Short lower-case name, as shown by `neuromesh info`.
    pub fn name(self) -> &'static str {
        match self {
            SomaKind::None => "none",
            SomaKind::SinglePoint => "single point",
            SomaKind::ThreePoint => "three-point",
            SomaKind::MultiPoint => "multi-point (contour or stack)",
        }
    }
}

/// The soma of one tree, fitted as a sphere.
#[derive(Debug, Clone, PartialEq)]
pub struct Soma {
    /// How the file states it.
    pub kind: SomaKind,
    /// The type-1 samples that make it up.
    pub samples: Vec<u32>,
    /// Sphere centre: the single sample, the 3-point centre, or the centroid.
    pub center: [f64; 3],
    /// Sphere radius as NeuroM defines it: the sample's radius, the 3-point soma's
    /// r, or the mean distance of the points to their centroid.
    pub radius: f64,
}

/// One connected tree of the file.
#[derive(Debug, Clone, PartialEq)]
pub struct Tree {
    /// Its root in the geometry tree (a soma sample when it has a soma).
    pub root: u32,
    /// Its soma, if it has type-1 samples.
    pub soma: Option<Soma>,
    /// Number of samples in it.
    pub len: u32,
}

/// What cleaning changed, so reports can show it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Cleaning {
    /// Samples merged into their parent because they sat at the same position.
    pub duplicates_merged: u32,
    /// Samples merged into an earlier one at exactly the same place, of the
    /// same type and with the same parent (or both roots): a subtree or a
    /// soma written twice.
    pub copies_merged: u32,
    /// Zero radii replaced.
    pub zero_radii: u32,
    /// Negative (or non-finite) radii replaced.
    pub negative_radii: u32,
    /// Missing radii that took a neighbour's radius.
    pub radii_from_neighbours: u32,
    /// Missing radii set from the tree's median segment length (no valid radius in the tree).
    pub radii_from_default: u32,
    /// Soma points whose missing radius was derived from their neighbours.
    pub soma_radius_fallbacks: u32,
    /// Cycles of parent links broken (the cycle's first sample in the file
    /// made a root).
    pub cycles_broken: u32,
}

/// A neuron skeleton: samples, tree and soma, with SWC ids only at the edge.
#[derive(Debug, Clone)]
pub struct Morphology {
    name: String,
    ids: Vec<i64>,
    kinds: Vec<i32>,
    pos: Vec<[f64; 3]>,
    radius: Vec<f64>,
    lines: Vec<u32>,
    file_parent: Vec<u32>,
    parent: Vec<u32>,
    child_start: Vec<u32>,
    child_list: Vec<u32>,
    order: Vec<u32>,
    tree_of: Vec<u32>,
    trees: Vec<Tree>,
    cleaning: Cleaning,
    comment_lines: usize,
    /// The line and ids of the first parent cycle broken.
    first_cycle: Option<(u32, String)>,
}

impl Morphology {
    /// A copy with coordinates and radii multiplied by `factor` (unit conversion).
    ///
    /// # Errors
    /// [`Error::InvalidParam`] if `factor` is not finite and positive.
    pub fn scaled(&self, factor: f64) -> Result<Self> {
        if !(factor.is_finite() && factor > 0.0) {
            return Err(Error::InvalidParam {
                name: "scale",
                reason: format!("must be finite and > 0, got {factor}"),
            });
        }
        let mut m = self.clone();
        if factor != 1.0 {
            for p in &mut m.pos {
                for c in p.iter_mut() {
                    *c *= factor;
                }
            }
            for r in &mut m.radius {
                *r *= factor;
            }
            for t in &mut m.trees {
                if let Some(s) = &mut t.soma {
                    for c in &mut s.center {
                        *c *= factor;
                    }
                    s.radius *= factor;
                }
            }
        }
        Ok(m)
    }

    /// The morphology moved by `offset` (positions and soma centres; radii
    /// unchanged).
    pub fn translated(mut self, offset: [f64; 3]) -> Self {
        let shift = |p: &mut [f64; 3]| {
            for a in 0..3 {
                p[a] += offset[a];
            }
        };
        self.pos.iter_mut().for_each(shift);
        for t in &mut self.trees {
            if let Some(s) = &mut t.soma {
                shift(&mut s.center);
            }
        }
        self
    }

    /// The box holding every sample's sphere: lowest and highest corner.
    /// Both are zero for an empty morphology.
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        if self.pos.is_empty() {
            return ([0.0; 3], [0.0; 3]);
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for (p, &r) in self.pos.iter().zip(&self.radius) {
            for a in 0..3 {
                lo[a] = lo[a].min(p[a] - r);
                hi[a] = hi[a].max(p[a] + r);
            }
        }
        (lo, hi)
    }

    /// The name used in messages: the file path or `<arrays>`.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Number of samples (after merging duplicates).
    pub fn len(&self) -> usize {
        self.ids.len()
    }
    /// Whether there are no samples (never true for a successfully built morphology).
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }
    /// SWC id of each sample.
    pub fn ids(&self) -> &[i64] {
        &self.ids
    }
    /// SWC type code of each sample.
    pub fn kinds(&self) -> &[i32] {
        &self.kinds
    }
    /// Position of each sample, in the file's units (times any scale applied).
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.pos
    }
    /// Cleaned radius of each sample (always > 0).
    pub fn radii(&self) -> &[f64] {
        &self.radius
    }
    /// 1-based line of each sample in its file (row + 1 for arrays).
    pub fn lines(&self) -> &[u32] {
        &self.lines
    }
    /// Parent index of each sample as the file links them (after merging
    /// duplicates), [`NO_PARENT`] for roots.
    pub fn file_parents(&self) -> &[u32] {
        &self.file_parent
    }
    /// Parent index in the geometry tree, which is re-rooted at the soma.
    pub fn parents(&self) -> &[u32] {
        &self.parent
    }
    /// Children of sample `i` in the geometry tree.
    pub fn children(&self, i: u32) -> &[u32] {
        let i = i as usize;
        &self.child_list[self.child_start[i] as usize..self.child_start[i + 1] as usize]
    }
    /// All samples, parents before children, tree by tree.
    pub fn order(&self) -> &[u32] {
        &self.order
    }
    /// Index of the tree each sample belongs to.
    pub fn tree_of(&self) -> &[u32] {
        &self.tree_of
    }
    /// The connected trees.
    pub fn trees(&self) -> &[Tree] {
        &self.trees
    }
    /// What cleaning changed.
    pub fn cleaning(&self) -> Cleaning {
        self.cleaning
    }
    /// Refuses the morphology if cleaning broke a cycle of parent links
    /// (for callers that would rather have the file fixed: `--strict`).
    ///
    /// # Errors
    /// [`Error::Swc`] at the line of the first cycle's first sample, with
    /// its ids.
    pub fn refuse_cycles(&self) -> Result<()> {
        match &self.first_cycle {
            None => Ok(()),
            Some((line, what)) => Err(Error::swc(
                &self.name,
                *line as usize,
                format!(
                    "{what} ({} cycles in the file; without --strict each is broken where it \
                     first appears in the file)",
                    self.cleaning.cycles_broken
                ),
            )),
        }
    }
    /// Comment lines in the source file.
    pub fn comment_lines(&self) -> usize {
        self.comment_lines
    }
    /// The soma kind of the morphology: that of the first tree with a soma.
    pub fn soma_kind(&self) -> SomaKind {
        self.trees
            .iter()
            .find_map(|t| t.soma.as_ref().map(|s| s.kind))
            .unwrap_or(SomaKind::None)
    }
    /// Whether sample `i` belongs to its tree's soma.
    pub fn is_soma(&self, i: u32) -> bool {
        let t = &self.trees[self.tree_of[i as usize] as usize];
        t.soma.as_ref().is_some_and(|s| s.samples.contains(&i))
    }
    /// Total neurite cable length: the sum of parent–child distances, soma–soma
    /// links excluded (as NeuroMorpho's "Total Length").
    pub fn cable_length(&self) -> f64 {
        let soma = self.soma_mask();
        (0..self.len())
            .filter(|&i| self.parent[i] != NO_PARENT)
            .filter(|&i| !(soma[i] && soma[self.parent[i] as usize]))
            .map(|i| dist(self.pos[i], self.pos[self.parent[i] as usize]))
            .sum()
    }
    /// One flag per sample: part of its tree's soma.
    pub fn soma_mask(&self) -> Vec<bool> {
        let mut mask = vec![false; self.len()];
        for t in &self.trees {
            if let Some(s) = &t.soma {
                for &i in &s.samples {
                    mask[i as usize] = true;
                }
            }
        }
        mask
    }
    /// Number of children of each geometry-tree node that has at least two,
    /// soma samples excluded: `(sample, child count)`.
    pub fn branch_points(&self) -> Vec<(u32, usize)> {
        let soma = self.soma_mask();
        (0..self.len() as u32)
            .filter(|&i| !soma[i as usize])
            .map(|i| (i, self.children(i).len()))
            .filter(|&(_, c)| c >= 2)
            .collect()
    }
}

pub(crate) fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::swc::SwcFile;

    fn morph(text: &str) -> Result<Morphology> {
        Morphology::from_file(SwcFile::parse(text.as_bytes(), "t.swc")?)
    }

    fn swc_err(text: &str) -> (usize, String) {
        match morph(text) {
            Err(Error::Swc(e)) => (e.line, e.reason),
            other => panic!("expected SWC error, got {other:?}"),
        }
    }

    #[test]
    fn missing_parent_names_the_childs_line() {
        let (line, reason) = swc_err("1 1 0 0 0 1 -1\n2 3 1 0 0 1 1\n3 3 2 0 0 1 99\n");
        assert_eq!(line, 3);
        assert!(reason.contains("parent id 99 does not exist"), "{reason}");
    }

    #[test]
    fn cycles_are_broken_at_their_first_sample_and_refused_on_request() {
        // 2 → 3 → 4 → 2, hanging nowhere; 5 below the cycle.
        let m =
            morph("1 1 0 0 0 1 -1\n2 3 1 0 0 1 3\n3 3 2 0 0 1 4\n4 3 2 1 0 1 2\n5 3 3 1 0 1 4\n")
                .unwrap();
        assert_eq!(m.len(), 5);
        assert_eq!(m.cleaning().cycles_broken, 1);
        // Sample 2 (the cycle's first in the file) is a root now.
        assert_eq!(m.file_parent[1], NO_PARENT);
        let Err(Error::Swc(e)) = m.refuse_cycles() else {
            panic!("a broken cycle is refused on request")
        };
        assert_eq!(e.line, 2);
        assert!(
            e.reason.contains("cycle: 2 → 3 → 4 → 2") || e.reason.contains("cycle"),
            "{}",
            e.reason
        );
        // Two cycles, both broken; a clean file refuses nothing.
        let m = morph("1 3 0 0 0 1 2\n2 3 1 0 0 1 1\n3 3 5 0 0 1 4\n4 3 6 0 0 1 3\n").unwrap();
        assert_eq!(m.cleaning().cycles_broken, 2);
        assert_eq!(m.trees().len(), 2);
        assert!(
            morph("1 1 0 0 0 1 -1\n2 3 1 0 0 1 1\n")
                .unwrap()
                .refuse_cycles()
                .is_ok()
        );
        let (line, reason) = swc_err("1 1 0 0 0 1 -1\n2 3 1 0 0 1 2\n");
        assert_eq!(line, 2);
        assert!(reason.contains("own parent"));
    }

    #[test]
    fn duplicates_merge_into_parent() {
        let m = morph("1 3 0 0 0 1 -1\n2 3 0 0 0 2 1\n3 3 1 0 0 1 2\n4 3 1 0 0 1 3\n").unwrap();
        assert_eq!(m.len(), 2);
        assert_eq!(m.cleaning().duplicates_merged, 2);
        assert_eq!(m.radii()[0], 2.0);
        assert_eq!(m.ids(), &[1, 3]);
    }

    #[test]
    fn fragments_on_one_soma_and_copied_subtrees_become_one_tree() {
        // Two fragments, each with the soma at the same place (the second a
        // little wider), sharing their first neurite sample; the second goes
        // on elsewhere.
        let m = morph(
            "1 1 0 0 0 5 -1\n2 3 10 0 0 1 1\n3 3 20 0 0 1 2\n\
             11 1 0 0 0 6 -1\n12 3 10 0 0 1 11\n13 3 10 10 0 1 12\n",
        )
        .unwrap();
        assert_eq!(m.trees().len(), 1);
        assert_eq!(m.len(), 4);
        assert_eq!(m.cleaning().copies_merged, 2);
        assert_eq!(m.radii()[0], 6.0);
        assert_eq!(m.ids(), &[1, 2, 3, 13]);
        assert_eq!(m.children(1), &[2, 3]);
        // The same place under different parents is not a copy.
        let m =
            morph("1 3 0 0 0 1 -1\n2 3 5 0 0 1 1\n3 3 0 5 0 1 1\n4 3 5 5 0 1 2\n5 3 5 5 0 1 3\n")
                .unwrap();
        assert_eq!(m.len(), 5);
        assert_eq!(m.cleaning().copies_merged, 0);
    }

    #[test]
    fn missing_radii_take_nearest_valid() {
        let m = morph("1 3 0 0 0 2 -1\n2 3 1 0 0 0 1\n3 3 2 0 0 -1 2\n4 3 3 0 0 5 3\n").unwrap();
        assert_eq!(m.radii(), &[2.0, 2.0, 5.0, 5.0]);
        assert_eq!(m.cleaning().zero_radii, 1);
        assert_eq!(m.cleaning().negative_radii, 1);
        assert_eq!(m.cleaning().radii_from_neighbours, 2);
    }

    #[test]
    fn all_zero_radii_use_median_segment() {
        let m = morph("1 3 0 0 0 0 -1\n2 3 2 0 0 0 1\n3 3 4 0 0 0 2\n").unwrap();
        assert!(m.radii().iter().all(|&r| (r - 0.5).abs() < 1e-12));
        assert_eq!(m.cleaning().radii_from_default, 3);
    }

    #[test]
    fn zero_radius_soma_uses_neighbours() {
        let m = morph("1 1 0 0 0 0 -1\n2 3 10 0 0 2 1\n3 3 20 0 0 1 2\n").unwrap();
        assert_eq!(m.radii()[0], 3.0);
        assert_eq!(m.trees()[0].soma.as_ref().unwrap().radius, 3.0);
        assert_eq!(m.cleaning().soma_radius_fallbacks, 1);
    }

    #[test]
    fn nan_radii_in_arrays_are_missing() {
        let m = Morphology::from_arrays(
            &[1, 2, 3],
            &[1, 3, 3],
            &[[0.0; 3], [10.0, 0.0, 0.0], [20.0, 0.0, 0.0]],
            &[5.0, f64::NAN, 1.0],
            &[-1, 1, 2],
        )
        .unwrap();
        // The radius of a neighbour one hop away (the soma's or the tip's).
        assert!([5.0, 1.0].contains(&m.radii()[1]), "{}", m.radii()[1]);
        assert_eq!(m.cleaning().radii_from_neighbours, 1);
        assert!(Morphology::from_arrays(&[1], &[1], &[[0.0; 3]], &[f64::INFINITY], &[-1]).is_err());
    }

    #[test]
    fn a_placeholder_soma_radius_uses_neighbours() {
        let m = morph("1 1 0 0 0 1e-30 -1\n2 3 10 0 0 2 1\n3 3 20 0 0 1 2\n").unwrap();
        assert_eq!(m.radii()[0], 3.0);
        assert_eq!(m.cleaning().soma_radius_fallbacks, 1);
        // A small soma point that is still a soma stays as written.
        let m = morph("1 1 0 0 0 0.1 -1\n2 3 10 0 0 2 1\n").unwrap();
        assert_eq!(m.radii()[0], 0.1);
        assert_eq!(m.cleaning().soma_radius_fallbacks, 0);
    }

    #[test]
    fn soma_kinds() {
        assert_eq!(
            morph("1 3 0 0 0 1 -1\n").unwrap().soma_kind(),
            SomaKind::None
        );
        assert_eq!(
            morph("1 1 0 0 0 1 -1\n").unwrap().soma_kind(),
            SomaKind::SinglePoint
        );
        let along_y = "1 1 0 0 0 3 -1\n2 1 0 -3 0 3 1\n3 1 0 3 0 3 1\n4 3 5 0 0 1 1\n";
        let m = morph(along_y).unwrap();
        assert_eq!(m.soma_kind(), SomaKind::ThreePoint);
        assert_eq!(m.trees()[0].soma.as_ref().unwrap().radius, 3.0);
        let (c, s) = (0.6f64.cos() * 3.0, 0.6f64.sin() * 3.0);
        let rotated = format!(
            "1 1 1 1 1 3 -1\n2 1 {} {} 1 3 1\n3 1 {} {} 1 3 1\n",
            1.0 + c,
            1.0 + s,
            1.0 - c,
            1.0 - s
        );
        assert_eq!(morph(&rotated).unwrap().soma_kind(), SomaKind::ThreePoint);
        let contour = "1 1 1 0 0 1 -1\n2 1 0 1 0 1 1\n3 1 -1 0 0 1 2\n4 1 0 -1 0 1 3\n";
        let m = morph(contour).unwrap();
        assert_eq!(m.soma_kind(), SomaKind::MultiPoint);
        assert!((m.trees()[0].soma.as_ref().unwrap().radius - 1.0).abs() < 1e-12);
    }

    #[test]
    fn reroots_at_a_soma_that_is_not_the_file_root() {
        // Root is a neurite sample; the soma sits in the middle of the chain.
        let m = morph("1 0 0 0 0 1 -1\n2 0 1 0 0 1 1\n3 1 2 0 0 2 2\n4 0 3 0 0 1 3\n").unwrap();
        let t = &m.trees()[0];
        assert_eq!(t.root, 2);
        assert_eq!(m.parents()[1], 2);
        assert_eq!(m.parents()[0], 1);
        assert_eq!(m.children(2), &[1, 3]);
        assert_eq!(m.file_parents()[2], 1);
    }

    #[test]
    fn several_roots_give_several_trees() {
        let m = morph("1 3 0 0 0 1 -1\n2 3 1 0 0 1 1\n3 3 5 0 0 1 -1\n4 3 6 0 0 1 3\n").unwrap();
        assert_eq!(m.trees().len(), 2);
        assert_eq!(m.tree_of(), &[0, 0, 1, 1]);
    }

    #[test]
    fn from_arrays_checks_lengths_and_rows() {
        let e = Morphology::from_arrays(&[1, 2], &[1], &[[0.0; 3]; 2], &[1.0; 2], &[-1, 1])
            .unwrap_err();
        assert!(
            e.to_string()
                .contains("<arrays>:1: ids has 2 rows but types has 1")
        );
        let e = Morphology::from_arrays(
            &[1, 2],
            &[1, 3],
            &[[0.0; 3], [1.0, 0.0, 0.0]],
            &[1.0; 2],
            &[-1, 7],
        )
        .unwrap_err();
        assert_eq!(e.to_string(), "<arrays>:2: parent id 7 does not exist");
    }

    #[test]
    fn scaling_converts_units() {
        let m = morph("1 1 0 0 0 1000 -1\n2 3 2000 0 0 500 1\n")
            .unwrap()
            .scaled(0.001)
            .unwrap();
        assert_eq!(m.positions()[1], [2.0, 0.0, 0.0]);
        assert_eq!(m.radii()[1], 0.5);
        assert_eq!(m.trees()[0].soma.as_ref().unwrap().radius, 1.0);
        assert!(m.scaled(-1.0).is_err());
    }

    #[test]
    fn cable_length_skips_soma_links() {
        let m = morph("1 1 0 0 0 1 -1\n2 1 0 1 0 1 1\n3 3 3 0 0 1 1\n4 3 3 4 0 1 3\n").unwrap();
        assert!((m.cable_length() - 7.0).abs() < 1e-12);
    }
}
