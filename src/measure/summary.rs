//! A summary of a morphology, as `neuromesh info` prints it.
//!
//! Everything here is read off the [`Morphology`]; nothing is meshed. The text
//! form is for people, [`Summary::to_json`] for scripts.

use std::collections::BTreeMap;
use std::fmt;

use crate::input::morphology::{Cleaning, Morphology, SomaKind};
use crate::measure::skeleton::SkeletonMeasures;

/// Facts about a morphology.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// File name or `<arrays>`.
    pub name: String,
    /// Samples after merging duplicates.
    pub samples: usize,
    /// Connected trees (roots).
    pub trees: usize,
    /// Soma kind of the first tree with a soma.
    pub soma_kind: SomaKind,
    /// Soma sphere centre and radius, if there is a soma.
    pub soma: Option<([f64; 3], f64)>,
    /// Neurites leaving the soma.
    pub soma_trunks: usize,
    /// Samples per SWC type code.
    pub types: BTreeMap<i32, usize>,
    /// Branch points (soma excluded) by number of children.
    pub branch_points: BTreeMap<usize, usize>,
    /// Samples without children.
    pub tips: usize,
    /// Total neurite cable length.
    pub cable_length: f64,
    /// Smallest and largest radius after cleaning.
    pub radius_range: (f64, f64),
    /// Bounding box of the samples.
    pub bbox: ([f64; 3], [f64; 3]),
    /// What cleaning changed.
    pub cleaning: Cleaning,
    /// Comment lines in the file.
    pub comment_lines: usize,
    /// Surface and volume from the skeleton (NeuroMorpho.Org style and the
    /// union of round cones).
    pub measures: SkeletonMeasures,
}

impl Summary {
    /// Summarises `m`, with the union of round cones measured too (see
    /// [`SkeletonMeasures::with_union`] for its cost).
    pub fn with_union(m: &Morphology) -> Summary {
        Summary {
            measures: SkeletonMeasures::with_union(m),
            ..Summary::of(m)
        }
    }

    /// Summarises `m`.
    pub fn of(m: &Morphology) -> Summary {
        let mut types = BTreeMap::new();
        for &k in m.kinds() {
            *types.entry(k).or_insert(0) += 1;
        }
        let mut branch_points = BTreeMap::new();
        for (_, c) in m.branch_points() {
            *branch_points.entry(c).or_insert(0) += 1;
        }
        let soma_mask = m.soma_mask();
        let tips = (0..m.len() as u32)
            .filter(|&i| m.children(i).is_empty() && !soma_mask[i as usize])
            .count();
        let soma_trunks = (0..m.len())
            .filter(|&i| {
                !soma_mask[i]
                    && m.parents()[i] != crate::input::morphology::NO_PARENT
                    && soma_mask[m.parents()[i] as usize]
            })
            .count();
        let soma = m
            .trees()
            .iter()
            .find_map(|t| t.soma.as_ref().map(|s| (s.center, s.radius)));
        let (lo, hi) = crate::kernel::vector::bounds(m.positions());
        let rmin = m.radii().iter().copied().fold(f64::INFINITY, f64::min);
        let rmax = m.radii().iter().copied().fold(0.0, f64::max);
        Summary {
            name: m.name().to_owned(),
            samples: m.len(),
            trees: m.trees().len(),
            soma_kind: m.soma_kind(),
            soma,
            soma_trunks,
            types,
            branch_points,
            tips,
            cable_length: m.cable_length(),
            radius_range: (rmin, rmax),
            bbox: (lo, hi),
            cleaning: m.cleaning(),
            comment_lines: m.comment_lines(),
            measures: SkeletonMeasures::of(m),
        }
    }

    /// The summary as a JSON object.
    pub fn to_json(&self) -> String {
        let types: Vec<String> = self
            .types
            .iter()
            .map(|(k, v)| format!("\"{k}\":{v}"))
            .collect();
        let bps: Vec<String> = self
            .branch_points
            .iter()
            .map(|(k, v)| format!("\"{k}\":{v}"))
            .collect();
        let soma = match self.soma {
            Some((c, r)) => format!(
                "{{\"center\":[{},{},{}],\"radius\":{}}}",
                c[0], c[1], c[2], r
            ),
            None => "null".to_owned(),
        };
        let c = &self.cleaning;
        format!(
            concat!(
                "{{\"file\":{},\"samples\":{},\"trees\":{},\"soma_kind\":\"{}\",\"soma\":{},",
                "\"soma_trunks\":{},\"types\":{{{}}},\"branch_points\":{{{}}},\"tips\":{},",
                "\"cable_length\":{},\"radius_min\":{},\"radius_max\":{},",
                "\"bbox\":[[{},{},{}],[{},{},{}]],\"comment_lines\":{},",
                "\"cleaning\":{{\"duplicates_merged\":{},\"copies_merged\":{},\"zero_radii\":{},\"negative_radii\":{},",
                "\"radii_from_neighbours\":{},\"radii_from_default\":{},\"soma_radius_fallbacks\":{},\"cycles_broken\":{}}},",
                "\"measures\":{{\"soma_surface\":{},\"total_surface\":{},\"total_volume\":{},",
                "\"union_area\":{},\"union_volume\":{}}}}}"
            ),
            json_string(&self.name),
            self.samples,
            self.trees,
            self.soma_kind.name(),
            soma,
            self.soma_trunks,
            types.join(","),
            bps.join(","),
            self.tips,
            self.cable_length,
            self.radius_range.0,
            self.radius_range.1,
            self.bbox.0[0],
            self.bbox.0[1],
            self.bbox.0[2],
            self.bbox.1[0],
            self.bbox.1[1],
            self.bbox.1[2],
            self.comment_lines,
            c.duplicates_merged,
            c.copies_merged,
            c.zero_radii,
            c.negative_radii,
            c.radii_from_neighbours,
            c.radii_from_default,
            c.soma_radius_fallbacks,
            c.cycles_broken,
            self.measures.soma_surface,
            self.measures.total_surface,
            self.measures.total_volume,
            self.measures
                .union
                .map_or("null".to_owned(), |u| u.area.to_string()),
            self.measures
                .union
                .map_or("null".to_owned(), |u| u.volume.to_string()),
        )
    }
}

/// A JSON string literal with the required escapes.
pub(crate) fn json_string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for ch in s.chars() {
        match ch {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "file            {}", self.name)?;
        writeln!(f, "samples         {}", self.samples)?;
        writeln!(f, "trees (roots)   {}", self.trees)?;
        match self.soma {
            Some((c, r)) => writeln!(
                f,
                "soma            {}, centre ({:.3}, {:.3}, {:.3}), radius {:.4}, {} trunks",
                self.soma_kind.name(),
                c[0],
                c[1],
                c[2],
                r,
                self.soma_trunks
            )?,
            None => writeln!(f, "soma            none")?,
        }
        let types: Vec<String> = self.types.iter().map(|(k, v)| format!("{k}:{v}")).collect();
        writeln!(f, "types           {}", types.join(" "))?;
        let total: usize = self.branch_points.values().sum();
        let bps: Vec<String> = self
            .branch_points
            .iter()
            .map(|(k, v)| format!("{v} with {k} children"))
            .collect();
        if total == 0 {
            writeln!(f, "branch points   0")?;
        } else {
            writeln!(f, "branch points   {total} ({})", bps.join(", "))?;
        }
        writeln!(f, "tips            {}", self.tips)?;
        writeln!(f, "cable length    {:.3}", self.cable_length)?;
        writeln!(
            f,
            "radius          {:.4} .. {:.4}",
            self.radius_range.0, self.radius_range.1
        )?;
        let (lo, hi) = self.bbox;
        writeln!(
            f,
            "bounding box    ({:.3}, {:.3}, {:.3}) .. ({:.3}, {:.3}, {:.3})",
            lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]
        )?;
        let k = &self.measures;
        writeln!(
            f,
            "surface         {:.3} (soma {:.3}; NeuroMorpho style: compartments as cylinders)",
            k.total_surface, k.soma_surface
        )?;
        writeln!(
            f,
            "volume          {:.3} (NeuroMorpho style)",
            k.total_volume
        )?;
        if let Some(u) = k.union {
            writeln!(
                f,
                "round cones     area {:.3}, volume {:.3} (their union, soma as one sphere)",
                u.area, u.volume
            )?;
        }
        let c = &self.cleaning;
        write!(
            f,
            "cleaning        {} duplicate points and {} copies merged; {} zero and {} negative radii replaced \
             ({} from neighbours, {} from the default); {} soma radius fallbacks; \
             {} parent cycles broken",
            c.duplicates_merged,
            c.copies_merged,
            c.zero_radii,
            c.negative_radii,
            c.radii_from_neighbours,
            c.radii_from_default,
            c.soma_radius_fallbacks,
            c.cycles_broken
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::swc::SwcFile;

    #[test]
    fn summarises_a_small_cell() {
        let text = "1 1 0 0 0 2 -1\n2 3 2 0 0 1 1\n3 3 4 0 0 1 2\n4 3 5 1 0 1 3\n5 3 5 -1 0 0 3\n6 3 5 0 1 1 3\n";
        let m = Morphology::from_file(SwcFile::parse(text.as_bytes(), "c.swc").unwrap()).unwrap();
        let s = Summary::of(&m);
        assert_eq!(s.samples, 6);
        assert_eq!(s.soma_trunks, 1);
        assert_eq!(s.branch_points.get(&3), Some(&1));
        assert_eq!(s.tips, 3);
        assert_eq!(s.cleaning.zero_radii, 1);
        let text = s.to_string();
        assert!(text.contains("1 with 3 children"), "{text}");
        let j = s.to_json();
        assert!(j.contains("\"branch_points\":{\"3\":1}"), "{j}");
        assert!(j.contains("\"soma_kind\":\"single point\""), "{j}");
    }

    #[test]
    fn json_strings_are_escaped() {
        assert_eq!(json_string("a\"b\\c\n"), "\"a\\\"b\\\\c\\n\"");
    }
}
