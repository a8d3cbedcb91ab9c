//! Seeded, neuron-like random trees of any size, as SWC text: the fixture of
//! the scaling benchmark (10 thousand to a million samples) and of tests that
//! need a big, valid, reproducible cell.
//!
//! The cell is a soma sphere with a few primary neurites. Every living tip
//! grows one sample per round along a persistent random walk pulled towards
//! the direction the tip was born with, with a spacing proportional to its
//! radius (as dense tracings have), tapers slowly, may fork (the child leaves
//! 25 to 70 degrees off, thinner) and may end; one tip always survives until
//! the requested number of samples is reached. The same `(samples, seed)`
//! always gives the same text, and a larger tree of a seed starts with the
//! smaller one's rounds.
//!
//! The arbor's density stays bounded as it grows, as a real cell's does: forks
//! stop while [`MAX_TIPS`] tips are alive, and the pull to each tip's heading
//! carries it into new space instead of back through the arbor (a pull away
//! from the soma would make siblings converge and cross). Forking without
//! bound would grow the tips exponentially and the arbor's extent only
//! linearly, so the crossings between branches would grow faster than the
//! samples and the scaling benchmark would measure the fixture's crowding
//! rather than the mesher.

use std::fmt::Write as _;

use glam::DVec3;

use crate::kernel::rng::Rng;

/// A growing tip.
struct Tip {
    parent: usize,
    pos: DVec3,
    dir: DVec3,
    /// The direction it was born with; the walk keeps being pulled back to it,
    /// so siblings diverge and the arbor spreads into new space.
    heading: DVec3,
    radius: f64,
    kind: u8,
}

/// Soma radius of the generated cell (micrometres).
pub const SOMA_RADIUS: f64 = 8.0;

/// Tips alive at once, at most: no tip forks while this many grow.
pub const MAX_TIPS: usize = 48;

/// Weight of the pull towards a tip's heading (its direction when it was
/// born) in each step, against 0.25 for the random turn.
const HEADING_PULL: f64 = 0.12;

/// An SWC text of a random neuron with exactly `samples` samples (at least 2):
/// one soma sample and neurites of types 2 (axon), 3 and 4 (dendrites).
pub fn random_neuron_swc(samples: usize, seed: u64) -> String {
    grow(samples, seed).0
}

/// [`random_neuron_swc`], and the most tips that were alive at once.
fn grow(samples: usize, seed: u64) -> (String, usize) {
    let samples = samples.max(2);
    let mut most_tips = 0;
    let mut rng = Rng::new(seed ^ 0x5EED_0000_0000_0000);
    let mut out = String::with_capacity(samples * 48);
    out.push_str("# random neuron from neuromesh::input::synthetic\n");
    let _ = writeln!(out, "# samples {samples}, seed {seed}");
    let _ = writeln!(out, "1 1 0 0 0 {SOMA_RADIUS} -1");
    let mut tips: Vec<Tip> = (0..5)
        .map(|i| {
            let dir = rng.unit();
            Tip {
                parent: 1,
                pos: dir * SOMA_RADIUS,
                dir,
                heading: dir,
                radius: if i == 0 { 1.0 } else { 1.5 + rng.f64() },
                kind: if i == 0 { 2 } else { 3 + (i % 2) as u8 },
            }
        })
        .collect();
    let mut id = 1;
    while id < samples {
        most_tips = most_tips.max(tips.len());
        let mut next: Vec<Tip> = Vec::with_capacity(tips.len() + 4);
        let alive = tips.len();
        for (k, mut tip) in tips.into_iter().enumerate() {
            if id >= samples {
                break;
            }
            id += 1;
            let step = (1.2 * tip.radius).clamp(0.25, 3.0);
            tip.dir = (tip.dir + 0.25 * rng.unit() + HEADING_PULL * tip.heading).normalize();
            tip.pos += tip.dir * step;
            tip.radius = (tip.radius * 0.998).max(0.15);
            let _ = writeln!(
                out,
                "{id} {} {:.4} {:.4} {:.4} {:.4} {}",
                tip.kind, tip.pos.x, tip.pos.y, tip.pos.z, tip.radius, tip.parent
            );
            tip.parent = id;
            // Tips alive now: those kept so far this round (with their
            // forks), this one and the `alive - k - 1` still to grow.
            let now = next.len() + alive - k;
            // The draw comes first so the sequence does not depend on the cap.
            let fork = rng.f64() < 0.02;
            if fork && now < MAX_TIPS {
                // A fork: the child leaves at 25-70 degrees, thinner.
                let side = tip.dir.cross(rng.unit()).normalize_or_zero();
                let angle = (25.0 + 45.0 * rng.f64()).to_radians();
                let dir = (tip.dir * angle.cos() + side * angle.sin()).normalize_or(tip.dir);
                next.push(Tip {
                    parent: id,
                    pos: tip.pos,
                    dir,
                    heading: dir,
                    radius: (tip.radius * (0.6 + 0.3 * rng.f64())).max(0.15),
                    kind: tip.kind,
                });
            }
            // Tips end now and then, but the last one standing never does.
            let last = k + 1 == alive && next.is_empty();
            if last || rng.f64() >= 0.004 {
                next.push(tip);
            }
        }
        tips = next;
    }
    (out, most_tips)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_size_and_reproducible() {
        for n in [2, 3, 50, 2_000] {
            let a = random_neuron_swc(n, 7);
            let rows = a.lines().filter(|l| !l.starts_with('#')).count();
            assert_eq!(rows, n);
            assert_eq!(a, random_neuron_swc(n, 7));
        }
        assert_ne!(random_neuron_swc(500, 1), random_neuron_swc(500, 2));
    }

    #[test]
    fn a_larger_tree_starts_with_the_smaller_one() {
        let rows = |n| {
            random_neuron_swc(n, 5)
                .lines()
                .filter(|l| !l.starts_with('#'))
                .map(str::to_owned)
                .collect::<Vec<_>>()
        };
        let (small, large) = (rows(3_000), rows(12_000));
        assert_eq!(small[..], large[..small.len()]);
    }

    #[test]
    fn the_arbor_stays_sparse_as_it_grows() {
        let (large, most) = grow(200_000, 1);
        assert!(most <= MAX_TIPS, "{most} tips alive at once");
        // Samples within 200 micrometres of the soma: the arbor moves on
        // into new space rather than filling the old (with unbounded forks
        // nearly all of them would lie there).
        let near = |text: &str| {
            text.lines()
                .filter(|l| !l.starts_with('#'))
                .filter(|l| {
                    let v: Vec<f64> = l
                        .split(' ')
                        .skip(2)
                        .take(3)
                        .map(|x| x.parse().unwrap())
                        .collect();
                    v[0] * v[0] + v[1] * v[1] + v[2] * v[2] < 200.0 * 200.0
                })
                .count()
        };
        let (at_50k, at_200k) = (near(&random_neuron_swc(50_000, 1)), near(&large));
        assert!(
            at_200k < at_50k * 3,
            "{at_50k} then {at_200k} samples near the soma"
        );
    }

    #[test]
    fn parses_as_one_tree_with_a_soma() {
        let text = random_neuron_swc(5_000, 3);
        let file =
            crate::input::swc::SwcFile::parse(text.as_bytes(), "random.swc").expect("valid SWC");
        let m = crate::Morphology::from_file(file).expect("a tree");
        assert_eq!(m.len(), 5_000);
        assert_eq!(m.trees().len(), 1);
        assert_eq!(m.soma_kind(), crate::SomaKind::SinglePoint);
    }
}
