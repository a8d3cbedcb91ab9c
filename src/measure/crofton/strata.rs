//! Stratified sampling of lines: each stratum's (primitive's or box's)
//! tally of line values, the allocation of the main round's lines to the
//! strata from the pilot's tallies, and each stratum's random stream.

use crate::kernel::rng::Rng;

/// Lines of the pilot round.
pub const PILOT: usize = 50_000;

/// The rounds' budgets of intervals computed, per line of their line
/// budgets: where a line costs more, a round takes fewer lines.
pub(super) const COST_PER_LINE: f64 = 1000.0;

/// The running mean and variance of one box's line values.
#[derive(Default, Clone, Copy)]
pub(super) struct Moments {
    pub(super) n: f64,
    pub(super) sum: f64,
    pub(super) squares: f64,
}

impl Moments {
    pub(super) fn add(&mut self, y: f64) {
        self.n += 1.0;
        self.sum += y;
        self.squares += y * y;
    }
    pub(super) fn merge(&mut self, other: &Moments) {
        self.n += other.n;
        self.sum += other.sum;
        self.squares += other.squares;
    }
    pub(super) fn mean(&self) -> f64 {
        if self.n > 0.0 { self.sum / self.n } else { 0.0 }
    }
    pub(super) fn variance(&self) -> f64 {
        (self.squares / self.n - self.mean().powi(2)).max(0.0)
    }
}

/// One box's lines: the values whose means are its shares of the union's
/// area and volume, and what its lines cost (in intervals).
#[derive(Default, Clone, Copy)]
pub(super) struct Tally {
    pub(super) area: Moments,
    pub(super) volume: Moments,
    pub(super) cost: f64,
}

impl Tally {
    pub(super) fn merge(&mut self, other: &Tally) {
        self.area.merge(&other.area);
        self.volume.merge(&other.volume);
        self.cost += other.cost;
    }
}

pub(super) fn totals(tallies: &[Tally]) -> (f64, f64) {
    tallies.iter().fold((0.0, 0.0), |(a, v), t| {
        (a + t.area.mean(), v + t.volume.mean())
    })
}

/// The main round's lines per stratum from the pilot's tallies: Neyman
/// allocation with costs, the value's spread (area and volume, each relative
/// to the union's) over the root of a line's cost, within the budgets of
/// `lines` lines and `lines · COST_PER_LINE` intervals; at least `least`
/// and at least as many as the pilot drew.
pub(super) fn allocate(pilot: &[Tally], lines: usize, least: u32) -> Vec<u32> {
    let (area, volume) = totals(pilot);
    let spreads: Vec<(f64, f64)> = pilot
        .iter()
        .map(|t| {
            let spread = (t.area.variance() / (area * area)
                + t.volume.variance() / (volume * volume))
                .sqrt();
            (
                if spread.is_finite() { spread } else { 0.0 },
                (t.cost / t.area.n).max(1.0),
            )
        })
        .collect();
    let by_lines: f64 = spreads.iter().map(|(s, c)| s / c.sqrt()).sum();
    let by_cost: f64 = spreads.iter().map(|(s, c)| s * c.sqrt()).sum();
    let scale = if by_lines > 0.0 {
        (lines as f64 / by_lines).min(lines as f64 * COST_PER_LINE / by_cost)
    } else {
        0.0
    };
    // Never fewer than the pilot drew there: a stratum whose few pilot
    // lines all missed what it holds looks certain, and starving it would
    // make the estimate usually low and rarely far too high.
    spreads
        .iter()
        .zip(pilot)
        .map(|((s, c), t)| ((scale * s / c.sqrt()).max(t.area.n).ceil() as u32).max(least))
        .collect()
}

/// The generator of one stratum (primitive or box) in one round.
pub(super) fn stream(seed: u64, stratum: usize) -> Rng {
    Rng::new(0xC50F_70A5 ^ seed ^ (stratum as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15))
}
