//! Stage 3, the tubes (paper §3.2, "Contour Connection"): every branch's
//! tube pieces, built in parallel, each into its own [`Surface`], and
//! appended in branch order, which keeps the output identical whatever the
//! number of threads.
//!
//! A tube is closed at its ends except where something will be joined to
//! it: a secondary's start and a later piece's start are spliced
//! ([`super::splice`]), a trunk's start is taken by its soma's
//! triangulation ([`super::soma`]). Each such start becomes a [`Join`] or a
//! trunk of a soma.

use glam::DVec3;

use super::coverage::Skipped;
use super::plan::{SomaPlan, Starts};
use super::splice::Join;
use super::surface::Surface;
use super::tube::Tube;
use super::tube::pieces::{self, Caps, Pieces};
use crate::mesh::BuildStats;
use crate::params::Params;
use crate::skeleton::Skeleton;
use crate::skeleton::branch::Attachment;

/// Branches whose tubes are built (in parallel) before they are appended to
/// the cell's surface: the per-branch surfaces of one chunk at a time are
/// alive beside the whole one, not those of the whole cell (which doubled
/// the peak memory of a million-sample tree).
const TUBE_CHUNK: usize = 256;

/// The surface after stage 3: every branch's tube pieces.
#[derive(Debug, Clone)]
pub struct Tubes {
    /// The pieces' vertices and triangles.
    pub surface: Surface,
    /// The pieces, in build order, with their triangle ranges and first
    /// rings.
    pub tubes: Vec<Tube>,
    /// The open starts to splice.
    pub joins: Vec<Join>,
    /// Each soma to build, with the tubes whose first ring it joins.
    pub somas: Vec<(SomaPlan, Vec<u32>)>,
    /// Counts so far.
    pub stats: BuildStats,
    /// The original segments whose contours no piece took and that reach
    /// out of what the pieces hold, with their branch ([`super::filler`]).
    pub segments: Vec<(u32, Skipped)>,
}

/// Stage 3 on `skeleton`, starting each branch where `starts` says.
pub fn build(skeleton: &Skeleton, starts: &Starts, params: &Params) -> Tubes {
    let Skeleton {
        geometry,
        branches,
        tracks,
        ..
    } = skeleton;
    let jobs: Vec<u32> = (0..branches.len() as u32)
        .filter(|&i| starts.start[i as usize].is_some())
        .collect();
    let mut stats = BuildStats {
        branches: branches.len() as u32,
        branches_hidden: (branches.len() - jobs.len()) as u32,
        ..BuildStats::default()
    };
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
        let start = starts.start[id as usize].unwrap_or(0);
        let labels = b.vertex_labels();
        let pieces = pieces::build_pieces(&mut surface, track, &labels, id, start, anchor, caps);
        (surface, pieces)
    };
    // Room for the whole cell at once: growing by doubling copies the
    // surface several times over. Caps and bridges add a few per cent to
    // the rings' vertices.
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
    let mut out = Tubes {
        surface: Surface::with_capacity(ring_vertices + ring_vertices / 8 + 1024),
        tubes: Vec::new(),
        joins: Vec::new(),
        somas: Vec::new(),
        stats: BuildStats::default(),
        segments: Vec::new(),
    };
    let mut first_tube: Vec<Option<u32>> = vec![None; branches.len()];
    for chunk in jobs.chunks(TUBE_CHUNK) {
        let built: Vec<(Surface, Pieces)> = crate::kernel::parallel::map(chunk, build_one);
        for ((local, pieces), &id) in built.into_iter().zip(chunk) {
            stats.contours_skipped += pieces.skipped;
            out.append(skeleton, starts, id, &local, pieces, &mut first_tube);
        }
    }
    out.somas = starts
        .somas
        .iter()
        .map(|plan| {
            let trunks = plan
                .trunks
                .iter()
                .filter_map(|&b| first_tube[b as usize])
                .collect();
            (plan.clone(), trunks)
        })
        .collect();
    out.stats = stats;
    out
}

impl Tubes {
    /// Appends branch `id`'s pieces, built into `local`, and the joins
    /// their open starts need; notes the branch's first tube.
    fn append(
        &mut self,
        skeleton: &Skeleton,
        starts: &Starts,
        id: u32,
        local: &Surface,
        pieces: Pieces,
        first_tube: &mut [Option<u32>],
    ) {
        let offset = self.surface.append(local);
        self.segments
            .extend(pieces.segments.into_iter().map(|g| (id, g)));
        for (piece_index, tube) in pieces.tubes.into_iter().enumerate() {
            let t = tube.appended_at(offset);
            let b = t.branch as usize;
            if piece_index == 0 {
                first_tube[b] = Some(self.tubes.len() as u32);
            }
            let toward: Option<DVec3> = match (piece_index, skeleton.branches[b].attachment) {
                (0, Attachment::Secondary { .. }) => Some(t.anchor),
                (0, Attachment::Soma { .. }) => starts.spliced_trunk[b],
                (0, Attachment::Root) => None,
                _ => Some(t.anchor),
            };
            if let Some(toward) = toward {
                self.joins.push(Join {
                    tube: self.tubes.len() as u32,
                    toward,
                });
            }
            self.tubes.push(t);
        }
    }
}
