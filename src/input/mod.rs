//! Stage 0, input: SWC text ([`swc`]) or columns to a clean
//! [`Morphology`](morphology::Morphology) (ids to indices, duplicates merged,
//! missing radii filled, soma found, trees rooted at their soma), and the
//! plausibility of its radii ([`plausibility`]). SWC ids stop here: every
//! later stage uses dense sample indices.
pub mod morphology;
#[cfg(any(test, feature = "internals"))]
pub mod mutate;
pub mod plausibility;
pub mod swc;
#[cfg(any(test, feature = "internals"))]
pub mod synthetic;
