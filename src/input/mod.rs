//! Input: SWC text and arrays to a clean [`Morphology`](morphology::Morphology).
pub mod morphology;
pub mod plausibility;
pub mod swc;
#[cfg(any(test, feature = "internals"))]
pub mod synthetic;
