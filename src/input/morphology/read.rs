//! The morphology's constructors: from an SWC file, from a parsed file,
//! from columns.

use std::collections::HashMap;

use super::Morphology;
use super::construct;
use crate::error::{Error, Result};
use crate::input::swc::{RawSample, SwcFile};

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
        construct::build(file)
    }

    /// Builds the morphology from columns (navis, NeuroM and MorphIO users have
    /// these already). `parents` holds parent *ids*, negative for roots; a NaN
    /// radius is missing and filled as a zero one is. Errors name `<arrays>` and
    /// the 1-based row.
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
            // A NaN radius is a missing one (navis writes NaN where a trace
            // has no radii) and is filled like a zero; an infinite one is an
            // error.
            if xyz[i].iter().any(|v| !v.is_finite()) || radii[i].is_infinite() {
                return Err(Error::swc(
                    NAME,
                    line,
                    "coordinates must be finite and the radius finite or NaN (missing)",
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
        construct::build(SwcFile {
            path: NAME.to_owned(),
            samples,
            comment_lines: 0,
        })
    }
}
