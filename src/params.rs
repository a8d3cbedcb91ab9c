//! Every tunable of the mesher, listed once.
//!
//! The table in [`with_params`] is the one place a parameter is declared:
//! its name, type, default and documentation. From it come [`Params`] (with
//! its `DEFAULT_*` constants and `with_*` builders), the CLI's flags (clap's
//! derive reads the same doc comments behind the `cli` feature), the Python
//! keyword arguments with their defaults and docstrings (the bindings expand
//! the same table), and [`Params::FIELDS`], from which a test checks the
//! Python stub and the README's parameter table. Adding a parameter is one
//! entry here and a range check in [`Params::validate`].

/// Calls the macro `$callback` with the parameter table, after the tokens
/// passed in brackets: per parameter its doc comment, `name: type = default`
/// (a literal), the constant holding the default and the builder's name.
macro_rules! with_params {
    ($callback:ident! { $($pass:tt)* }) => {
        $callback! {
            [$($pass)*]

            /// Best-successor tie threshold t, in degrees (paper §3.1).
            ///
            /// When the two straightest children of a branch point deviate
            /// from the incoming direction by angles closer than this, the
            /// child whose radius is closest to the branch point's continues
            /// the branch.
            angle_threshold: f64 = 10.0 => DEFAULT_ANGLE_THRESHOLD, with_angle_threshold;

            /// Extra spline samples per segment, k1 of formula (1).
            ///
            /// Between two original points the resampler inserts
            /// floor(D / r_avg × resolution) + k1 samples; the first segment
            /// of a branch gets k1 + 1 (the paper's endpoint rule).
            k1: u32 = 1 => DEFAULT_K1, with_k1;

            /// Fewest vertices on a contour (even, formula 3's floor).
            ///
            /// Formula (3) gives few vertices where the radius is near the
            /// branch average; this floor keeps thin tubes round (12 keeps a
            /// tube's area and volume within 1 % of the round tube's).
            min_vertices: u32 = 12 => DEFAULT_MIN_VERTICES, with_min_vertices;

            /// Most vertices on a contour (even, formula 3's cap).
            ///
            /// Caps the count where a thick point sits on a thin branch.
            max_vertices: u32 = 64 => DEFAULT_MAX_VERTICES, with_max_vertices;

            /// Shrinking rings in each tip cap before its apex.
            ///
            /// Tips are closed by a dome inside the last sample's sphere;
            /// more rings make it rounder. 0 closes a tip with a flat fan.
            cap_rings: u32 = 3 => DEFAULT_CAP_RINGS, with_cap_rings;

            /// Global resolution factor (edge length = r_avg / resolution).
            ///
            /// Multiplies the sampling density along branches (formula 1)
            /// and around contours (formula 3). 2 gives about four times the
            /// triangles.
            resolution: f64 = 1.0 => DEFAULT_RESOLUTION, with_resolution;

            /// Smallest radius used, in output units (0 = automatic).
            ///
            /// Radii below it are raised to it. Whatever its value, radii
            /// are never below 1e-5 × the longest side of the cell's box
            /// (wherever the cell lies), so the f32 output keeps contours
            /// distinct; every raised radius is reported.
            min_radius: f64 = 0.0 => DEFAULT_MIN_RADIUS, with_min_radius;

            /// Factor applied to coordinates and radii (unit conversion).
            ///
            /// For example 0.001 turns nanometres into micrometres, 0.008
            /// turns 8 nm voxels into micrometres.
            scale: f64 = 1.0 => DEFAULT_SCALE, with_scale;

            /// Most triangles a mesh may be estimated to need (0 = no limit).
            ///
            /// Before building, the mesher counts the triangles formulas (1)
            /// and (3) ask for; a cell that passes this is refused with the
            /// line of the segment that asks for most (radii in the wrong
            /// unit, an outlying coordinate) instead of running for minutes
            /// and exhausting memory. The estimate is of the mesh before
            /// straight stretches are thinned: 100 M is about 4 GB of work.
            face_limit: u32 = 100_000_000 => DEFAULT_FACE_LIMIT, with_face_limit;
        }
    };
}
#[cfg(feature = "python")]
pub(crate) use with_params;

/// One parameter as the table declares it, for generated documentation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Field {
    /// Its name: the field, the Python keyword, and with `-` for `_` the
    /// CLI flag.
    pub name: &'static str,
    /// Its Rust type (`f64` or `u32`).
    pub rust_type: &'static str,
    /// Its default, as written in the table.
    pub default: &'static str,
    /// Its doc comment: a first line that says what it is, then why.
    pub doc: &'static str,
}

impl Field {
    /// Its Python type.
    pub fn python_type(&self) -> &'static str {
        match self.rust_type {
            "f64" => "float",
            _ => "int",
        }
    }

    /// The first line of its doc: what it is.
    pub fn summary(&self) -> &'static str {
        self.doc.lines().next().unwrap_or("").trim()
    }

    /// The rest of its doc, joined into one paragraph: why.
    pub fn details(&self) -> String {
        let rest: Vec<&str> = self
            .doc
            .lines()
            .skip(1)
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .collect();
        rest.join(" ")
    }
}

macro_rules! define_params {
    ([] $( $(#[doc = $doc:literal])* $name:ident : $ty:ident = $default:tt => $const:ident, $with:ident; )*) => {
        $(
            #[doc = concat!("Default of [`Params::", stringify!($name), "`].")]
            pub const $const: $ty = $default;
        )*

        /// The names of all parameters, as CLI flags (with `-` for `_`) and
        /// Python keywords, in table order.
        pub const PARAM_NAMES: &[&str] = &[$(stringify!($name)),*];

        /// Tunables of the meshing pipeline, each with the paper formula it
        /// feeds.
        #[derive(Debug, Clone, Copy, PartialEq)]
        #[non_exhaustive]
        #[cfg_attr(feature = "cli", derive(clap::Args))]
        pub struct Params {
            $(
                $(#[doc = $doc])*
                #[doc = ""]
                #[doc = concat!("Default ", stringify!($default), ".")]
                #[cfg_attr(feature = "cli", arg(long, default_value_t = $const, help_heading = "Mesh parameters"))]
                pub $name: $ty,
            )*
        }

        impl Params {
            /// All defaults.
            pub const DEFAULT: Params = Params { $($name: $const),* };

            /// Every parameter as the table declares it, in table order.
            pub const FIELDS: &[Field] = &[$(
                Field {
                    name: stringify!($name),
                    rust_type: stringify!($ty),
                    default: stringify!($default),
                    doc: concat!($($doc, "\n"),*),
                }
            ),*];

            $(
                #[doc = concat!("Sets [`Params::", stringify!($name), "`].")]
                pub const fn $with(mut self, value: $ty) -> Self {
                    self.$name = value;
                    self
                }
            )*
        }
    };
}

with_params!(define_params! {});

impl Default for Params {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl Params {
    /// Checks every value against its valid range.
    ///
    /// # Errors
    /// [`crate::Error::InvalidParam`] naming the first bad parameter.
    pub fn validate(&self) -> crate::Result<()> {
        let bad =
            |name: &'static str, reason: String| Err(crate::Error::InvalidParam { name, reason });
        if !(self.angle_threshold.is_finite() && (0.0..=180.0).contains(&self.angle_threshold)) {
            return bad(
                "angle_threshold",
                format!("must be in [0, 180] degrees, got {}", self.angle_threshold),
            );
        }
        if self.k1 > 64 {
            return bad("k1", format!("must be at most 64, got {}", self.k1));
        }
        if !(4..=1024).contains(&self.min_vertices) || !self.min_vertices.is_multiple_of(2) {
            return bad(
                "min_vertices",
                format!("must be even and in [4, 1024], got {}", self.min_vertices),
            );
        }
        if !(4..=1024).contains(&self.max_vertices) || !self.max_vertices.is_multiple_of(2) {
            return bad(
                "max_vertices",
                format!("must be even and in [4, 1024], got {}", self.max_vertices),
            );
        }
        if self.max_vertices < self.min_vertices {
            return bad(
                "max_vertices",
                format!(
                    "must be at least min_vertices ({}), got {}",
                    self.min_vertices, self.max_vertices
                ),
            );
        }
        if self.cap_rings > 64 {
            return bad(
                "cap_rings",
                format!("must be at most 64, got {}", self.cap_rings),
            );
        }
        if !(self.resolution.is_finite() && self.resolution > 0.0 && self.resolution <= 16.0) {
            return bad(
                "resolution",
                format!("must be in (0, 16], got {}", self.resolution),
            );
        }
        if !(self.min_radius.is_finite() && self.min_radius >= 0.0) {
            return bad(
                "min_radius",
                format!("must be finite and >= 0, got {}", self.min_radius),
            );
        }
        if !(self.scale.is_finite() && self.scale > 0.0) {
            return bad(
                "scale",
                format!("must be finite and > 0, got {}", self.scale),
            );
        }
        Ok(())
    }

    /// The keyword arguments of the Python stub, one per line with `indent`:
    /// `name: type = default,`.
    pub fn python_stub_arguments(indent: &str) -> String {
        Self::FIELDS
            .iter()
            .map(|f| format!("{indent}{}: {} = {},\n", f.name, f.python_type(), f.default))
            .collect()
    }

    /// The README's table of parameters (Markdown).
    pub fn markdown_table() -> String {
        let mut out = String::from("| name | default | meaning |\n| --- | --- | --- |\n");
        for f in Self::FIELDS {
            out += &format!("| `{}` | {} | {} |\n", f.name, f.default, f.summary());
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid() {
        Params::DEFAULT.validate().unwrap();
        assert_eq!(Params::default(), Params::DEFAULT);
    }

    #[test]
    fn each_bad_value_names_its_parameter() {
        let cases: [(Params, &str); 9] = [
            (
                Params::DEFAULT.with_angle_threshold(200.0),
                "angle_threshold",
            ),
            (Params::DEFAULT.with_k1(65), "k1"),
            (Params::DEFAULT.with_min_vertices(7), "min_vertices"),
            (Params::DEFAULT.with_max_vertices(2), "max_vertices"),
            (
                Params::DEFAULT.with_min_vertices(16).with_max_vertices(8),
                "max_vertices",
            ),
            (Params::DEFAULT.with_cap_rings(100), "cap_rings"),
            (Params::DEFAULT.with_resolution(0.0), "resolution"),
            (Params::DEFAULT.with_min_radius(f64::NAN), "min_radius"),
            (Params::DEFAULT.with_scale(-1.0), "scale"),
        ];
        for (p, name) in cases {
            match p.validate() {
                Err(crate::Error::InvalidParam { name: n, .. }) => assert_eq!(n, name),
                other => panic!("{name}: {other:?}"),
            }
        }
    }

    #[test]
    fn the_table_gives_every_field_its_default_and_doc() {
        assert_eq!(Params::FIELDS.len(), PARAM_NAMES.len());
        let f = Params::FIELDS[0];
        assert_eq!(
            (f.name, f.rust_type, f.default),
            ("angle_threshold", "f64", "10.0")
        );
        assert!(f.summary().starts_with("Best-successor tie threshold"));
        assert!(f.details().starts_with("When the two straightest"));
        for f in Params::FIELDS {
            assert!(
                !f.summary().is_empty() && !f.details().is_empty(),
                "{}",
                f.name
            );
        }
        assert_eq!(DEFAULT_K1, 1);
        assert_eq!(Params::DEFAULT.with_k1(2).k1, 2);
    }

    /// The Python stub and the README list the parameters as the table does:
    /// `NEUROMESH_BLESS=1 cargo test` rewrites both from it.
    #[test]
    fn the_stub_and_the_readme_follow_the_table() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let bless = std::env::var_os("NEUROMESH_BLESS").is_some();
        let stub = root.join("python/neuromesh_rs/_native.pyi");
        let readme = root.join("README.md");
        let arguments = |indent: &str| Params::python_stub_arguments(indent);
        let table = |_: &str| Params::markdown_table();
        type Generated<'a> = &'a dyn Fn(&str) -> String;
        let files: [(&std::path::Path, Generated, &str, &str); 2] = [
            (&stub, &arguments, "# params:begin", "# params:end"),
            (
                &readme,
                &table,
                "<!-- params:begin -->",
                "<!-- params:end -->",
            ),
        ];
        for (path, generated, begin, end) in files {
            let text = std::fs::read_to_string(path).expect("readable");
            let blocks = replace_blocks(&text, begin, end, generated);
            assert!(blocks.1 > 0, "{} has no {begin:?} block", path.display());
            if bless {
                std::fs::write(path, &blocks.0).expect("writable");
            } else {
                assert!(
                    blocks.0 == text,
                    "{} does not list the parameters as params.rs does; \
                     run NEUROMESH_BLESS=1 cargo test --lib params",
                    path.display()
                );
            }
        }
    }

    /// `text` with the lines between every `begin` and `end` marker line
    /// (compared trimmed) replaced by `with` of the marker's indentation,
    /// and how many blocks there were.
    fn replace_blocks(
        text: &str,
        begin: &str,
        end: &str,
        with: &dyn Fn(&str) -> String,
    ) -> (String, usize) {
        let (mut out, mut inside, mut n) = (String::new(), false, 0);
        for line in text.split_inclusive('\n') {
            if inside {
                if line.trim() == end {
                    inside = false;
                    out += line;
                }
                continue;
            }
            out += line;
            if line.trim() == begin {
                inside = true;
                n += 1;
                out += &with(&line[..line.len() - line.trim_start().len()]);
            }
        }
        (out, n)
    }
}
