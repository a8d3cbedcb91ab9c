//! What a mesh is judged by: the quality report ([`check`], [`report`]:
//! closed, manifold, outward, self-intersections, split into the
//! construction's and the skeleton's own overlaps) and the reference it is
//! compared with, the exact union of the skeleton's round cones ([`union`],
//! integrated along random lines by [`crofton`]), beside the skeleton's own
//! measures as NeuroMorpho.Org reports them ([`skeleton`]) and the summary
//! `neuromesh info` prints ([`summary`]).
pub mod check;
pub mod crofton;
pub mod fidelity;
pub mod report;
pub mod skeleton;
pub mod summary;
pub mod union;
