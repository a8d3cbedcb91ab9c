//! The mesh quality report: what [`Mesh::check`](crate::Mesh::check) found,
//! its verdicts, and its forms for people (`Display`, the `neuromesh check`
//! table) and for scripts ([`MeshReport::to_json`]).

use crate::measure::fidelity::Fidelity;
use crate::measure::skeleton::SkeletonMeasures;
use crate::mesh::BuildStats;

/// At most this many intersecting pairs are listed in a report (all are counted).
pub const MAX_LISTED_PAIRS: usize = 100;

/// What [`Mesh::check`](crate::Mesh::check) found.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MeshReport {
    /// Vertices in the mesh.
    pub vertices: usize,
    /// Triangles in the mesh.
    pub faces: usize,
    /// Distinct undirected edges.
    pub edges: usize,
    /// Edges used by one face only (holes).
    pub boundary_edges: usize,
    /// Edges used by more than two faces.
    pub nonmanifold_edges: usize,
    /// Two-face edges whose faces run the edge the same way (flipped neighbours).
    pub misoriented_edges: usize,
    /// Vertices whose faces form more than one fan (pinches).
    pub nonmanifold_vertices: usize,
    /// Vertices no face uses.
    pub unreferenced_vertices: usize,
    /// Faces with a repeated vertex or (near) zero area.
    pub degenerate_faces: usize,
    /// Faces that repeat another face's three vertices.
    pub duplicate_faces: usize,
    /// Connected components (by shared vertices).
    pub components: usize,
    /// Components whose signed volume is negative (facing inward).
    pub inward_components: usize,
    /// V − E + F over the used vertices (2 per closed sphere-like component).
    pub euler_characteristic: i64,
    /// Surface area.
    pub area: f64,
    /// Signed enclosed volume.
    pub volume: f64,
    /// Pairs of triangles that intersect and are not neighbours.
    pub self_intersections: usize,
    /// Of those, pairs made by the construction (only with a morphology).
    pub construction_intersections: Option<usize>,
    /// Of those, pairs where the skeleton itself overlaps (only with a morphology).
    pub skeleton_overlaps: Option<usize>,
    /// Area of the faces whose vertices all belong to a soma (only with a
    /// morphology).
    pub soma_area: Option<f64>,
    /// The skeleton's own measures (only with a morphology): NeuroMorpho.Org
    /// style and the union of round cones.
    pub skeleton: Option<SkeletonMeasures>,
    /// The mesh point by point against the union of the skeleton's round
    /// cones: samples outside, vertices' deviation (only with a morphology).
    pub fidelity: Option<Fidelity>,
    /// Up to 100 intersecting face pairs, smallest first.
    pub intersecting_pairs: Vec<[u32; 2]>,
    /// How the mesh was built (zeros for meshes read from files).
    pub stats: BuildStats,
}

impl MeshReport {
    /// Every edge is in exactly two faces.
    pub fn is_closed(&self) -> bool {
        self.boundary_edges == 0 && self.nonmanifold_edges == 0
    }
    /// Edge- and vertex-manifold.
    pub fn is_manifold(&self) -> bool {
        self.nonmanifold_edges == 0 && self.nonmanifold_vertices == 0
    }
    /// Neighbouring faces agree on orientation and every component faces outward.
    pub fn is_outward(&self) -> bool {
        self.misoriented_edges == 0 && self.inward_components == 0
    }
    /// A sound surface: closed, manifold, outward, no degenerate or
    /// duplicate faces and no self-intersection at all (whether the
    /// construction or the skeleton made it).
    pub fn is_sound(&self) -> bool {
        self.is_closed()
            && self.is_manifold()
            && self.is_outward()
            && self.degenerate_faces == 0
            && self.duplicate_faces == 0
            && self.self_intersections == 0
    }

    /// Every skeleton sample inside and the vertices within the deviation
    /// bounds of the union of round cones (see
    /// [`Fidelity::is_faithful`]); true when no morphology was given.
    pub fn is_faithful(&self) -> bool {
        self.fidelity.as_ref().is_none_or(Fidelity::is_faithful)
    }

    /// Sound and, with a morphology, faithful.
    pub fn is_valid(&self) -> bool {
        self.is_sound() && self.is_faithful()
    }

    /// The report as a JSON object (stable keys, for scripts and the CLI).
    pub fn to_json(&self) -> String {
        let opt = |v: Option<usize>| v.map_or("null".to_owned(), |v| v.to_string());
        let pairs: Vec<String> = self
            .intersecting_pairs
            .iter()
            .map(|p| format!("[{},{}]", p[0], p[1]))
            .collect();
        let s = &self.stats;
        format!(
            concat!(
                "{{\"vertices\":{},\"faces\":{},\"edges\":{},\"closed\":{},\"manifold\":{},\"outward\":{},",
                "\"valid\":{},\"boundary_edges\":{},\"nonmanifold_edges\":{},\"misoriented_edges\":{},",
                "\"nonmanifold_vertices\":{},\"unreferenced_vertices\":{},\"degenerate_faces\":{},",
                "\"duplicate_faces\":{},\"components\":{},\"inward_components\":{},",
                "\"euler_characteristic\":{},\"area\":{},\"volume\":{},\"self_intersections\":{},",
                "\"construction_intersections\":{},\"skeleton_overlaps\":{},\"soma_area\":{},\"skeleton\":{},",
                "\"sound\":{},\"faithful\":{},\"fidelity\":{},",
                "\"intersecting_pairs\":[{}],",
                "\"build\":{{\"branches\":{},\"branches_hidden\":{},\"contours_skipped\":{},",
                "\"junctions_paper\":{},\"junctions_moved\":{},\"junctions_fallback\":{},",
                "\"junctions_detached\":{},\"soma_trunks\":{},\"overlap_pairs\":{},",
                "\"overlap_pairs_left\":{},\"fillers\":{},\"samples_merged\":{},",
                "\"radii_filled\":{},\"soma_radii_replaced\":{},\"cycles_broken\":{},\"radii_raised\":{}}}}}"
            ),
            self.vertices,
            self.faces,
            self.edges,
            self.is_closed(),
            self.is_manifold(),
            self.is_outward(),
            self.is_valid(),
            self.boundary_edges,
            self.nonmanifold_edges,
            self.misoriented_edges,
            self.nonmanifold_vertices,
            self.unreferenced_vertices,
            self.degenerate_faces,
            self.duplicate_faces,
            self.components,
            self.inward_components,
            self.euler_characteristic,
            json_f64(self.area),
            json_f64(self.volume),
            self.self_intersections,
            opt(self.construction_intersections),
            opt(self.skeleton_overlaps),
            self.soma_area.map_or("null".to_owned(), json_f64),
            self.skeleton.map_or("null".to_owned(), |k| format!(
                "{{\"soma_surface\":{},\"total_surface\":{},\"total_volume\":{},\"union_area\":{},\"union_volume\":{}}}",
                json_f64(k.soma_surface),
                json_f64(k.total_surface),
                json_f64(k.total_volume),
                k.union.map_or("null".to_owned(), |u| json_f64(u.area)),
                k.union.map_or("null".to_owned(), |u| json_f64(u.volume))
            )),
            self.is_sound(),
            self.is_faithful(),
            self.fidelity.as_ref().map_or("null".to_owned(), fidelity_json),
            pairs.join(","),
            s.branches,
            s.branches_hidden,
            s.contours_skipped,
            s.junctions_paper,
            s.junctions_moved,
            s.junctions_fallback,
            s.junctions_detached,
            s.soma_trunks,
            s.overlap_pairs,
            s.overlap_pairs_left,
            s.fillers,
            s.samples_merged,
            s.radii_filled,
            s.soma_radii_replaced,
            s.cycles_broken,
            s.radii_raised,
        )
    }
}

fn fidelity_json(f: &Fidelity) -> String {
    let d = &f.deviation;
    let three = |v: [f64; 3]| v.map(json_f64).join(",");
    let outside: Vec<String> = f.outside.iter().map(u32::to_string).collect();
    format!(
        concat!(
            "{{\"samples\":{},\"samples_outside\":{},\"outside\":[{}],",
            "\"deviation_radii\":[{}],\"deviation\":[{}],\"sme\":{}}}"
        ),
        f.samples,
        f.samples_outside,
        outside.join(","),
        three(d.radii),
        three(d.units),
        json_f64(d.mean)
    )
}

fn json_f64(v: f64) -> String {
    if v.is_finite() {
        format!("{v}")
    } else {
        "null".to_owned()
    }
}

impl std::fmt::Display for MeshReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let yes = |b: bool| if b { "yes" } else { "NO" };
        writeln!(f, "vertices              {}", self.vertices)?;
        writeln!(f, "faces                 {}", self.faces)?;
        writeln!(
            f,
            "closed                {} ({} boundary edges)",
            yes(self.is_closed()),
            self.boundary_edges
        )?;
        writeln!(
            f,
            "manifold              {} ({} edges, {} vertices non-manifold)",
            yes(self.is_manifold()),
            self.nonmanifold_edges,
            self.nonmanifold_vertices
        )?;
        writeln!(
            f,
            "outward               {} ({} flipped edges, {} inward components)",
            yes(self.is_outward()),
            self.misoriented_edges,
            self.inward_components
        )?;
        writeln!(f, "components            {}", self.components)?;
        writeln!(f, "euler characteristic  {}", self.euler_characteristic)?;
        writeln!(f, "degenerate faces      {}", self.degenerate_faces)?;
        writeln!(f, "duplicate faces       {}", self.duplicate_faces)?;
        match (self.construction_intersections, self.skeleton_overlaps) {
            (Some(c), Some(s)) => writeln!(
                f,
                "self-intersections    {} pairs ({c} from construction, {s} from skeleton overlaps)",
                self.self_intersections
            )?,
            _ => writeln!(f, "self-intersections    {} pairs", self.self_intersections)?,
        }
        writeln!(f, "area                  {:.6}", self.area)?;
        writeln!(f, "volume                {:.6}", self.volume)?;
        if let Some(a) = self.soma_area {
            writeln!(f, "soma area             {a:.6}")?;
        }
        if self.skeleton.is_some() {
            writeln!(
                f,
                "input changed         {} samples merged, {} radii filled, {} soma radii replaced, {} cycles broken, {} radii raised to the floor",
                self.stats.samples_merged,
                self.stats.radii_filled,
                self.stats.soma_radii_replaced,
                self.stats.cycles_broken,
                self.stats.radii_raised
            )?;
        }
        if let Some(k) = self.skeleton {
            let rel = |a: f64, b: f64| 100.0 * (a / b - 1.0);
            if let Some(u) = k.union {
                writeln!(
                    f,
                    "union of round cones  area {:.6} (mesh {:+.2} %), volume {:.6} (mesh {:+.2} %); radii before the floor",
                    u.area,
                    rel(self.area, u.area),
                    u.volume,
                    rel(self.volume, u.volume)
                )?;
            }
            writeln!(
                f,
                "NeuroMorpho-style     soma surface {:.6}, total surface {:.6}, total volume {:.6}",
                k.soma_surface, k.total_surface, k.total_volume
            )?;
        }
        if let Some(fi) = &self.fidelity {
            writeln!(
                f,
                "samples inside        {} ({} of {} outside)",
                yes(fi.samples_outside == 0),
                fi.samples_outside,
                fi.samples
            )?;
            let d = &fi.deviation;
            writeln!(
                f,
                "deviation             median {:.3}, 95 % {:.3}, worst {:.3} local radii ({:.4}, {:.4}, {:.4}); mean {:.4}",
                d.radii[0], d.radii[1], d.radii[2], d.units[0], d.units[1], d.units[2], d.mean
            )?;
        }
        let s = &self.stats;
        if s.branches > 0 {
            writeln!(
                f,
                "junctions             {} paper, {} moved, {} fallback, {} detached",
                s.junctions_paper, s.junctions_moved, s.junctions_fallback, s.junctions_detached
            )?;
            writeln!(
                f,
                "overlaps              {} crossing pairs of parts, {} left after the union ({} fillers)",
                s.overlap_pairs, s.overlap_pairs_left, s.fillers
            )?;
        }
        if self.fidelity.is_some() {
            writeln!(f, "sound                 {}", yes(self.is_sound()))?;
            writeln!(f, "faithful              {}", yes(self.is_faithful()))?;
        }
        write!(f, "valid                 {}", yes(self.is_valid()))
    }
}
