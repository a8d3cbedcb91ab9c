//! Raw samples → an index tree with a soma and clean radii (pipeline step 1).
//!
//! SWC ids stop here: every later stage sees dense `u32` sample indices into the
//! arrays of [`Morphology`]. Those indices are also what a mesh vertex carries
//! (`vertex_sample`), so `morphology.ids()[vertex_sample[v]]` is the SWC id a
//! vertex was made from.
//!
//! What happens, in order:
//!
//! 1. **Ids → indices.** A parent id that does not exist and a cycle of parent
//!    links are errors with the line of the offending sample.
//! 2. **Duplicate consecutive points** (a sample at its parent's position, as
//!    neuTube and Simple Neurite Tracer write them) are merged into the parent: the
//!    parent keeps the larger radius and adopts the children.
//! 3. **Radii.** A radius that is zero, negative or not finite is *missing*. Each
//!    missing radius takes the radius of the nearest sample (in tree hops) whose
//!    radius is valid. A tree with no valid radius at all (some tracers write only
//!    zeros) gets `0.25 ×` its median segment length: thin enough to keep
//!    neighbouring branches apart, thick enough to mesh. A soma point with a missing
//!    radius gets `1.5 ×` the largest radius among its neighbours, so its trunks fit.
//!    The counts of all three go into [`Cleaning`].
//! 4. **Soma and roots.** The type-1 samples of a tree form its soma; when several
//!    groups exist the largest is the soma and the others are ordinary samples. A
//!    tree with a soma is re-rooted there (hemibrain files root the tree elsewhere),
//!    so every neurite leaves the soma; see [`SomaKind`] for how it is classified.
//!
//! Units are the file's own; [`Morphology::scaled`] converts (nm → µm is 0.001).

use std::collections::{HashMap, VecDeque};

use crate::error::{Error, Result};
use crate::swc::{RawSample, SwcFile};

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
}

impl Morphology {
    /// Reads an SWC file and builds the morphology.
    ///
    /// # Errors
    /// [`Error::Io`] when the file cannot be read; [`Error::Swc`] naming the line
    /// for malformed content, a missing parent or a cycle.
    ///
    /// # Example
    /// ```
    /// let m = neuromesh::Morphology::from_swc("tests/data/y_bifurcation.swc")?;
    /// assert_eq!(m.trees().len(), 1);
    /// # Ok::<(), neuromesh::Error>(())
    /// ```
    pub fn from_swc(path: impl AsRef<std::path::Path>) -> Result<Self> {
        Self::from_file(SwcFile::read(path)?)
    }

    /// Builds the morphology from an already parsed file.
    ///
    /// # Errors
    /// [`Error::Swc`] for a missing parent or a cycle.
    pub fn from_file(file: SwcFile) -> Result<Self> {
        build(file)
    }

    /// Builds the morphology from columns (navis, NeuroM and MorphIO users have
    /// these already). `parents` holds parent *ids*, negative for roots. Errors
    /// name `<arrays>` and the 1-based row.
    ///
    /// # Errors
    /// [`Error::Swc`] when the columns differ in length, a value is not finite, an
    /// id repeats, a parent is missing or the links form a cycle.
    pub fn from_arrays(
        ids: &[i64],
        types: &[i32],
        xyz: &[[f64; 3]],
        radii: &[f64],
        parents: &[i64],
    ) -> Result<Self> {
        const NAME: &str = "<arrays>";
        let n = ids.len();
        for (what, len) in [
            ("types", types.len()),
            ("xyz", xyz.len()),
            ("radii", radii.len()),
            ("parents", parents.len()),
        ] {
            if len != n {
                return Err(Error::swc(
                    NAME,
                    1,
                    format!("ids has {n} rows but {what} has {len}"),
                ));
            }
        }
        if n == 0 {
            return Err(Error::swc(NAME, 1, "no samples: the arrays are empty"));
        }
        let mut samples = Vec::with_capacity(n);
        let mut seen = HashMap::with_capacity(n);
        for i in 0..n {
            let line = i + 1;
            if xyz[i].iter().any(|v| !v.is_finite()) || !radii[i].is_finite() {
                return Err(Error::swc(
                    NAME,
                    line,
                    "coordinates and radius must be finite",
                ));
            }
            if ids[i] < 0 {
                return Err(Error::swc(
                    NAME,
                    line,
                    format!("id must not be negative, found {}", ids[i]),
                ));
            }
            if let Some(prev) = seen.insert(ids[i], line) {
                return Err(Error::swc(
                    NAME,
                    line,
                    format!("duplicate id {} (first defined on row {prev})", ids[i]),
                ));
            }
            samples.push(RawSample {
                id: ids[i],
                kind: types[i],
                pos: xyz[i],
                radius: radii[i],
                parent: if parents[i] < 0 { -1 } else { parents[i] },
                line: line as u32,
            });
        }
        build(SwcFile {
            path: NAME.to_owned(),
            samples,
            comment_lines: 0,
        })
    }

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

fn build(file: SwcFile) -> Result<Morphology> {
    let SwcFile {
        path,
        samples,
        comment_lines,
    } = file;
    let n = samples.len();
    let index: HashMap<i64, u32> = samples
        .iter()
        .enumerate()
        .map(|(i, s)| (s.id, i as u32))
        .collect();
    let mut parent = vec![NO_PARENT; n];
    for (i, s) in samples.iter().enumerate() {
        if s.parent >= 0 {
            if s.parent == s.id {
                return Err(Error::swc(
                    &path,
                    s.line as usize,
                    format!("sample {} is its own parent", s.id),
                ));
            }
            parent[i] = *index.get(&s.parent).ok_or_else(|| {
                Error::swc(
                    &path,
                    s.line as usize,
                    format!("parent id {} does not exist", s.parent),
                )
            })?;
        }
    }
    check_acyclic(&samples, &parent, &path)?;

    // Merge duplicate consecutive points. The tolerance is relative to the
    // skeleton's extent so it works in nm and in µm alike.
    let extent = samples
        .iter()
        .flat_map(|s| s.pos)
        .fold(0f64, |m, v| m.max(v.abs()))
        .max(1e-30);
    let eps = 1e-9 * extent;
    let mut merged_into: Vec<u32> = (0..n as u32).collect();
    let mut radius: Vec<f64> = samples.iter().map(|s| s.radius).collect();
    let mut cleaning = Cleaning::default();
    for s in &samples {
        if !s.radius.is_finite() || s.radius < 0.0 {
            cleaning.negative_radii += 1;
        } else if s.radius == 0.0 {
            cleaning.zero_radii += 1;
        }
    }
    // Process in an order where parents come first so chains of duplicates collapse.
    let file_order = topological_order(&parent);
    for &i in &file_order {
        let i = i as usize;
        let p = parent[i];
        if p == NO_PARENT {
            continue;
        }
        let target = find(&mut merged_into, p);
        if dist(samples[i].pos, samples[target as usize].pos) <= eps
            && samples[i].kind == samples[target as usize].kind
        {
            merged_into[i] = target;
            if radius[i].is_finite() && radius[i] > radius[target as usize] {
                radius[target as usize] = radius[i];
            }
            cleaning.duplicates_merged += 1;
        }
    }
    // Compact the survivors, keeping file order.
    let mut new_index = vec![NO_PARENT; n];
    let mut kept = Vec::with_capacity(n);
    for i in 0..n {
        if merged_into[i] == i as u32 {
            new_index[i] = kept.len() as u32;
            kept.push(i);
        }
    }
    let m = kept.len();
    let mut file_parent = vec![NO_PARENT; m];
    for (k, &i) in kept.iter().enumerate() {
        let p = parent[i];
        if p != NO_PARENT {
            file_parent[k] = new_index[find(&mut merged_into, p) as usize];
        }
    }
    let ids: Vec<i64> = kept.iter().map(|&i| samples[i].id).collect();
    let kinds: Vec<i32> = kept.iter().map(|&i| samples[i].kind).collect();
    let pos: Vec<[f64; 3]> = kept.iter().map(|&i| samples[i].pos).collect();
    let lines: Vec<u32> = kept.iter().map(|&i| samples[i].line).collect();
    let mut radius: Vec<f64> = kept.iter().map(|&i| radius[i]).collect();

    // Undirected adjacency, for tree discovery, re-rooting and radius filling.
    let mut degree = vec![0u32; m + 1];
    for (k, &p) in file_parent.iter().enumerate() {
        if p != NO_PARENT {
            degree[k] += 1;
            degree[p as usize] += 1;
        }
    }
    let adj_start = prefix_sum(&degree);
    let mut fill = adj_start.clone();
    let mut adj = vec![0u32; *adj_start.last().unwrap_or(&0) as usize];
    for (k, &p) in file_parent.iter().enumerate() {
        if p != NO_PARENT {
            adj[fill[k] as usize] = p;
            fill[k] += 1;
            adj[fill[p as usize] as usize] = k as u32;
            fill[p as usize] += 1;
        }
    }
    let neighbours = |k: usize| &adj[adj_start[k] as usize..adj_start[k + 1] as usize];

    // Trees: connected components, discovered from file roots in file order.
    let mut tree_of = vec![NO_PARENT; m];
    let mut components: Vec<Vec<u32>> = Vec::new();
    for root in 0..m {
        if file_parent[root] != NO_PARENT || tree_of[root] != NO_PARENT {
            continue;
        }
        let t = components.len() as u32;
        let mut members = vec![root as u32];
        tree_of[root] = t;
        let mut head = 0;
        while head < members.len() {
            let k = members[head] as usize;
            head += 1;
            for &q in neighbours(k) {
                if tree_of[q as usize] == NO_PARENT {
                    tree_of[q as usize] = t;
                    members.push(q);
                }
            }
        }
        components.push(members);
    }

    fill_missing_radii(
        &mut radius,
        &pos,
        &file_parent,
        &components,
        &kinds,
        &adj_start,
        &adj,
        &mut cleaning,
    );

    // Soma per tree, then re-root every tree at its soma (or keep the file root).
    let mut trees = Vec::with_capacity(components.len());
    let mut geo_parent = vec![NO_PARENT; m];
    let mut order = Vec::with_capacity(m);
    for members in &components {
        let soma_samples = largest_soma_group(members, &kinds, &neighbours);
        let root = soma_samples.first().copied().unwrap_or(members[0]);
        // BFS over undirected edges gives the re-rooted parent links.
        let start = order.len();
        order.push(root);
        geo_parent[root as usize] = NO_PARENT;
        let mut head = start;
        while head < order.len() {
            let k = order[head];
            head += 1;
            for &q in neighbours(k as usize) {
                if q != root && geo_parent[q as usize] == NO_PARENT && q != geo_parent[k as usize] {
                    geo_parent[q as usize] = k;
                    order.push(q);
                }
            }
        }
        let soma = fit_soma(&soma_samples, &pos, &radius);
        trees.push(Tree {
            root,
            soma,
            len: members.len() as u32,
        });
    }

    let mut counts = vec![0u32; m + 1];
    for &p in &geo_parent {
        if p != NO_PARENT {
            counts[p as usize] += 1;
        }
    }
    let child_start = prefix_sum(&counts);
    let mut fill = child_start.clone();
    let mut child_list = vec![0u32; m - trees.len()];
    // Children in file order, which keeps the output deterministic and familiar.
    for (k, &p) in geo_parent.iter().enumerate() {
        if p != NO_PARENT {
            child_list[fill[p as usize] as usize] = k as u32;
            fill[p as usize] += 1;
        }
    }

    Ok(Morphology {
        name: path,
        ids,
        kinds,
        pos,
        radius,
        lines,
        file_parent,
        parent: geo_parent,
        child_start,
        child_list,
        order,
        tree_of,
        trees,
        cleaning,
        comment_lines,
    })
}

fn prefix_sum(counts: &[u32]) -> Vec<u32> {
    let mut start = Vec::with_capacity(counts.len());
    let mut acc = 0u32;
    for &c in counts {
        start.push(acc);
        acc += c;
    }
    start
}

fn find(merged_into: &mut [u32], mut i: u32) -> u32 {
    while merged_into[i as usize] != i {
        let next = merged_into[i as usize];
        merged_into[i as usize] = merged_into[next as usize];
        i = next;
    }
    i
}

/// Parents before children; assumes the links are acyclic.
fn topological_order(parent: &[u32]) -> Vec<u32> {
    let n = parent.len();
    let mut counts = vec![0u32; n + 1];
    for &p in parent {
        if p != NO_PARENT {
            counts[p as usize] += 1;
        }
    }
    let start = prefix_sum(&counts);
    let mut fill = start.clone();
    let mut children = vec![0u32; n];
    let mut roots = Vec::new();
    for (i, &p) in parent.iter().enumerate() {
        if p == NO_PARENT {
            roots.push(i as u32);
        } else {
            children[fill[p as usize] as usize] = i as u32;
            fill[p as usize] += 1;
        }
    }
    let mut order = roots;
    let mut head = 0;
    while head < order.len() {
        let k = order[head] as usize;
        head += 1;
        order.extend_from_slice(&children[start[k] as usize..start[k + 1] as usize]);
    }
    order
}

fn check_acyclic(samples: &[RawSample], parent: &[u32], path: &str) -> Result<()> {
    let order = topological_order(parent);
    if order.len() == samples.len() {
        return Ok(());
    }
    let mut reached = vec![false; samples.len()];
    for &i in &order {
        reached[i as usize] = true;
    }
    // Every unreached sample is in a cycle or hangs below one; walk up from the
    // first one (in file order) until a sample repeats to find the cycle itself.
    let start = reached.iter().position(|r| !r).unwrap_or(0);
    let mut seen = HashMap::new();
    let mut walk = Vec::new();
    let mut k = start as u32;
    while !seen.contains_key(&k) {
        seen.insert(k, walk.len());
        walk.push(k);
        k = parent[k as usize];
    }
    let cycle = &walk[seen[&k]..];
    let first = cycle
        .iter()
        .copied()
        .min_by_key(|&i| samples[i as usize].line)
        .unwrap_or(k);
    let ids: Vec<String> = cycle
        .iter()
        .take(8)
        .map(|&i| samples[i as usize].id.to_string())
        .collect();
    let more = if cycle.len() > 8 { " → …" } else { "" };
    Err(Error::swc(
        path,
        samples[first as usize].line as usize,
        format!(
            "parent links form a cycle: {} → {}{more}",
            ids.join(" → "),
            samples[cycle[0] as usize].id
        ),
    ))
}

fn fill_missing_radii(
    radius: &mut [f64],
    pos: &[[f64; 3]],
    parent: &[u32],
    components: &[Vec<u32>],
    kinds: &[i32],
    adj_start: &[u32],
    adj: &[u32],
    cleaning: &mut Cleaning,
) {
    let valid = |r: f64| r.is_finite() && r > 0.0;
    let missing: Vec<bool> = radius.iter().map(|&r| !valid(r)).collect();
    let _ = &missing;
    let neighbours = |k: usize| &adj[adj_start[k] as usize..adj_start[k + 1] as usize];
    // Soma points first: their neighbours' radii decide the fallback.
    for k in 0..radius.len() {
        if missing[k] && kinds[k] == 1 {
            let best = neighbours(k)
                .iter()
                .map(|&q| radius[q as usize])
                .filter(|&r| valid(r))
                .fold(0f64, f64::max);
            if best > 0.0 {
                radius[k] = 1.5 * best;
                cleaning.soma_radius_fallbacks += 1;
            }
        }
    }
    // Multi-source BFS from every valid radius: a missing radius takes the value
    // of the nearest valid sample in tree hops.
    let mut queue: VecDeque<u32> = (0..radius.len() as u32)
        .filter(|&k| valid(radius[k as usize]))
        .collect();
    let mut done: Vec<bool> = radius.iter().map(|&r| valid(r)).collect();
    while let Some(k) = queue.pop_front() {
        for &q in neighbours(k as usize) {
            if !done[q as usize] {
                done[q as usize] = true;
                radius[q as usize] = radius[k as usize];
                cleaning.radii_from_neighbours += 1;
                queue.push_back(q);
            }
        }
    }
    // Trees without a single valid radius.
    for members in components {
        if members.iter().all(|&k| done[k as usize]) {
            continue;
        }
        let mut seg: Vec<f64> = members
            .iter()
            .filter(|&&k| parent[k as usize] != NO_PARENT)
            .map(|&k| dist(pos[k as usize], pos[parent[k as usize] as usize]))
            .filter(|&d| d > 0.0)
            .collect();
        seg.sort_by(f64::total_cmp);
        let median = seg.get(seg.len() / 2).copied().unwrap_or(1.0);
        let r = 0.25 * median;
        for &k in members {
            if !done[k as usize] {
                radius[k as usize] = if kinds[k as usize] == 1 { 1.5 * r } else { r };
                if kinds[k as usize] == 1 {
                    cleaning.soma_radius_fallbacks += 1;
                } else {
                    cleaning.radii_from_default += 1;
                }
            }
        }
    }
}

/// The largest connected group of type-1 samples in a tree (empty if none).
fn largest_soma_group<'a>(
    members: &[u32],
    kinds: &[i32],
    neighbours: &impl Fn(usize) -> &'a [u32],
) -> Vec<u32> {
    let mut best: Vec<u32> = Vec::new();
    let mut seen: HashMap<u32, ()> = HashMap::new();
    for &s in members {
        if kinds[s as usize] != 1 || seen.contains_key(&s) {
            continue;
        }
        let mut group = vec![s];
        seen.insert(s, ());
        let mut head = 0;
        while head < group.len() {
            let k = group[head];
            head += 1;
            for &q in neighbours(k as usize) {
                if kinds[q as usize] == 1 && !seen.contains_key(&q) {
                    seen.insert(q, ());
                    group.push(q);
                }
            }
        }
        if group.len() > best.len() {
            best = group;
        }
    }
    best
}

fn fit_soma(samples: &[u32], pos: &[[f64; 3]], radius: &[f64]) -> Option<Soma> {
    let (&first, _) = samples.split_first()?;
    let p = |i: u32| pos[i as usize];
    if samples.len() == 1 {
        return Some(Soma {
            kind: SomaKind::SinglePoint,
            samples: samples.to_vec(),
            center: p(first),
            radius: radius[first as usize],
        });
    }
    if samples.len() == 3
        && let Some((center, r)) = three_point(samples, pos, radius)
    {
        return Some(Soma {
            kind: SomaKind::ThreePoint,
            samples: samples.to_vec(),
            center,
            radius: r,
        });
    }
    let k = samples.len() as f64;
    let mut c = [0.0; 3];
    for &i in samples {
        for a in 0..3 {
            c[a] += p(i)[a] / k;
        }
    }
    let mean_dist = samples.iter().map(|&i| dist(p(i), c)).sum::<f64>() / k;
    // Coincident soma points have no spread: fall back to their mean radius.
    let r = if mean_dist > 0.0 {
        mean_dist
    } else {
        samples.iter().map(|&i| radius[i as usize]).sum::<f64>() / k
    };
    Some(Soma {
        kind: SomaKind::MultiPoint,
        samples: samples.to_vec(),
        center: c,
        radius: r,
    })
}

/// Recognises NeuroMorpho's 3-point soma in any orientation: one point with the
/// two others at ±r from it, on opposite sides.
fn three_point(samples: &[u32], pos: &[[f64; 3]], radius: &[f64]) -> Option<([f64; 3], f64)> {
    for (ci, &c) in samples.iter().enumerate() {
        let others: Vec<u32> = samples
            .iter()
            .enumerate()
            .filter(|&(j, _)| j != ci)
            .map(|(_, &s)| s)
            .collect();
        let pc = pos[c as usize];
        let r = radius[c as usize];
        let (a, b) = (pos[others[0] as usize], pos[others[1] as usize]);
        let (da, db) = (dist(a, pc), dist(b, pc));
        let mid = [
            (a[0] + b[0]) / 2.0,
            (a[1] + b[1]) / 2.0,
            (a[2] + b[2]) / 2.0,
        ];
        let tol = 0.05 * r.max(da).max(db);
        if r > 0.0 && (da - r).abs() <= tol && (db - r).abs() <= tol && dist(mid, pc) <= tol {
            return Some((pc, r));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn cycle_is_reported_with_its_ids() {
        let (line, reason) =
            swc_err("1 1 0 0 0 1 -1\n2 3 1 0 0 1 3\n3 3 2 0 0 1 4\n4 3 2 0 0 1 2\n");
        assert_eq!(line, 2);
        assert!(reason.contains("cycle"), "{reason}");
        assert!(reason.contains('2') && reason.contains('3') && reason.contains('4'));
        let (line, reason) = swc_err("1 1 0 0 0 1 -1\n2 3 1 0 0 1 2\n");
        assert_eq!(line, 2);
        assert!(reason.contains("own parent"));
    }

    #[test]
    fn unsorted_ids_and_parents_after_children() {
        let m = morph("5 3 2 0 0 1 9\n9 1 0 0 0 2 -1\n7 3 1 0 0 1 9\n").unwrap();
        assert_eq!(m.len(), 3);
        assert_eq!(m.trees().len(), 1);
        assert_eq!(m.trees()[0].root, 1);
        assert_eq!(m.children(1), &[0, 2]);
        assert_eq!(m.order()[0], 1);
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
