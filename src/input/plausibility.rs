//! A warning for radii that cannot be in the coordinates' units.
//!
//! Some tracing platforms write codes or voxel-scaled values into the SWC radius
//! column (the CAR platform's files hold radii of thousands on a cell a few
//! hundred units wide).
//! The mesher follows the radii as given, so such a file meshes into a blob, or
//! into a few tubes when most contours are swallowed by their neighbours. This
//! changes the mesh only in leaving out the fillers ([`crate::build::filler`]),
//! which would cross each other everywhere inside such swollen spheres; it
//! lets the CLI say why the mesh looks wrong.

use crate::input::morphology::{Morphology, NO_PARENT};

/// Median neurite radius above this many median segment lengths is implausible
/// (real tracings sit near 0.1 to 5; EM skeletons reach about 5).
pub const RADIUS_PER_SEGMENT: f64 = 20.0;

impl Morphology {
    /// Why the radii look like another unit than the coordinates, if they
    /// do: the median neurite radius is over 20 median segment lengths
    /// (`RADIUS_PER_SEGMENT`), or the largest neurite radius exceeds the
    /// bounding box's diagonal.
    pub fn radius_warning(&self) -> Option<String> {
        radius_warning(self)
    }
}

fn radius_warning(m: &Morphology) -> Option<String> {
    let (pos, rad, parent) = (m.positions(), m.radii(), m.parents());
    let neurite: Vec<usize> = (0..m.len()).filter(|&i| !m.is_soma(i as u32)).collect();
    let mut lengths: Vec<f64> = neurite
        .iter()
        .filter(|&&i| parent[i] != NO_PARENT)
        .map(|&i| distance(pos[i], pos[parent[i] as usize]))
        .filter(|&l| l > 0.0)
        .collect();
    let mut radii: Vec<f64> = neurite.iter().map(|&i| rad[i]).collect();
    if lengths.is_empty() || radii.is_empty() {
        return None;
    }
    let (length, radius) = (median(&mut lengths), median(&mut radii));
    let largest = radii.iter().copied().fold(0.0, f64::max);
    let (lo, hi) = crate::kernel::vector::bounds(pos);
    let diagonal = distance(lo, hi);
    let mut why = Vec::new();
    if radius > RADIUS_PER_SEGMENT * length {
        why.push(format!(
            "the median neurite radius {} is {} times the median segment length {}",
            shown(radius),
            if radius / length < 1e7 {
                format!("{:.0}", radius / length)
            } else {
                format!("{:.3e}", radius / length)
            },
            shown(length)
        ));
    }
    if diagonal > 0.0 && largest > diagonal {
        why.push(format!(
            "the largest neurite radius {} exceeds the bounding box's diagonal {}",
            shown(largest),
            shown(diagonal)
        ));
    }
    (!why.is_empty()).then(|| {
        format!(
            "radii look implausible: {}; the radius column may hold codes or another unit \
             than the coordinates (the mesh follows the radii as given)",
            why.join(", and ")
        )
    })
}

/// A number as a message shows it: four decimals, or in scientific notation
/// where it is very large or very small (a radius of 1e300 is not printed in
/// 300 digits).
fn shown(x: f64) -> String {
    if x == 0.0 || (1e-3..1e7).contains(&x.abs()) {
        format!("{x:.4}")
    } else {
        format!("{x:.3e}")
    }
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

fn median(v: &mut [f64]) -> f64 {
    let k = v.len() / 2;
    *v.select_nth_unstable_by(k, f64::total_cmp).1
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chain(radius: f64) -> Morphology {
        let mut text = String::from("1 1 0 0 0 5 -1\n");
        for i in 2..40 {
            text.push_str(&format!("{i} 3 {} 0 0 {radius} {}\n", 5 + i, i - 1));
        }
        let file = crate::input::swc::SwcFile::parse(text.as_bytes(), "chain.swc").expect("valid");
        Morphology::from_file(file).expect("a tree")
    }

    #[test]
    fn plausible_radii_pass_and_coded_ones_are_named() {
        assert_eq!(radius_warning(&chain(0.5)), None);
        assert_eq!(radius_warning(&chain(4.0)), None);
        let w = radius_warning(&chain(300.0)).expect("a warning");
        assert!(w.contains("300 times the median segment length"), "{w}");
        assert!(w.contains("exceeds the bounding box's diagonal"), "{w}");
    }
}
