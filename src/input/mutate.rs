//! Hostile variants of a real SWC file, for the fuzz test (`tests/fuzz.rs`)
//! and the long run by hand (`examples/fuzz.rs`).
//!
//! Each mutation is one thing real files or careless tools do, or one
//! extreme number: coordinates far out, radii scaled into another unit, a
//! star of children, zero or tiny radii, a byte-order mark, a parent cycle,
//! lines lost or repeated, garbage in a field, a file cut short, a second
//! copy of the cell on the first (coincident somas), jitter, other line
//! endings. The mesher must answer each with a mesh that passes its check
//! or with a clear error, in bounded time.

use crate::kernel::rng::Rng;

/// The mutations, by name.
pub const KINDS: [&str; 16] = [
    "far coordinates",
    "every coordinate scaled",
    "extreme radius",
    "neurite radii scaled",
    "star of children",
    "zero radii",
    "tiny soma radius",
    "byte-order mark",
    "parent cycle",
    "lines deleted",
    "line repeated",
    "garbage field",
    "file cut short",
    "coincident copy",
    "jitter",
    "line endings",
];

/// One SWC data line, split into its seven fields (and any extra ones).
struct Line {
    fields: Vec<String>,
}

impl Line {
    fn num(&self, k: usize) -> f64 {
        self.fields[k].parse().unwrap_or(0.0)
    }
    fn set(&mut self, k: usize, v: f64) {
        self.fields[k] = format!("{v:e}");
    }
}

/// The text split into comment lines (kept in place) and data lines.
fn split(text: &str) -> (Vec<Option<Line>>, Vec<String>) {
    let mut lines = Vec::new();
    let mut raw = Vec::new();
    for l in text.lines() {
        let fields: Vec<String> = l.split_whitespace().map(str::to_owned).collect();
        let data = !l.trim_start().starts_with('#') && fields.len() >= 7;
        lines.push(data.then_some(Line { fields }));
        raw.push(l.to_owned());
    }
    (lines, raw)
}

fn join(lines: &[Option<Line>], raw: &[String]) -> String {
    let mut out = String::new();
    for (l, r) in lines.iter().zip(raw) {
        match l {
            Some(l) => out.push_str(&l.fields.join(" ")),
            None => out.push_str(r),
        }
        out.push('\n');
    }
    out
}

/// One more than the largest id of the data lines `data`.
fn next_id(lines: &[Option<Line>], data: &[usize]) -> i64 {
    data.iter()
        .filter_map(|&i| lines[i].as_ref()?.fields[0].parse::<i64>().ok())
        .max()
        .unwrap_or(0)
        + 1
}

fn pick<T: Copy>(rng: &mut Rng, items: &[T]) -> T {
    items[(rng.next_u64() % items.len() as u64) as usize]
}

fn index(rng: &mut Rng, n: usize) -> usize {
    (rng.next_u64() % n.max(1) as u64) as usize
}

/// `text` mutated by mutation `kind` (an index into [`KINDS`]) with the
/// random choices of `rng`; `None` when the file has no data line.
pub fn mutate(text: &str, kind: usize, rng: &mut Rng) -> Option<String> {
    let (mut lines, raw) = split(text);
    let data: Vec<usize> = (0..lines.len()).filter(|&i| lines[i].is_some()).collect();
    if data.is_empty() {
        return None;
    }
    let any = |rng: &mut Rng| data[index(rng, data.len())];
    let line = |lines: &mut Vec<Option<Line>>, i: usize| lines[i].take().expect("a data line");
    match kind % KINDS.len() {
        0 => {
            let value = pick(rng, &[1e8, 1e15, 1e30, 3e38, -1e12]);
            for _ in 0..1 + index(rng, 3) {
                let i = any(rng);
                let mut l = line(&mut lines, i);
                l.set(2 + index(rng, 3), value);
                lines[i] = Some(l);
            }
        }
        1 => {
            let factor = pick(rng, &[1e20, 1e-20, 1e6, -1.0]);
            for &i in &data {
                let mut l = line(&mut lines, i);
                for k in 2..5 {
                    let v = l.num(k) * factor;
                    l.set(k, v);
                }
                lines[i] = Some(l);
            }
        }
        2 => {
            let i = any(rng);
            let mut l = line(&mut lines, i);
            l.set(5, pick(rng, &[1e300, 5e-324, 1e-30, 1e12, -1e300]));
            lines[i] = Some(l);
        }
        3 => {
            let factor = pick(rng, &[1e-3, 1e-6, 1e-9, 1e3]);
            for &i in &data {
                let mut l = line(&mut lines, i);
                if l.fields[1] != "1" {
                    let v = l.num(5) * factor;
                    l.set(5, v);
                }
                lines[i] = Some(l);
            }
        }
        4 => return Some(star(lines, raw, &data, rng)),
        5 => {
            let all = rng.next_u64().is_multiple_of(2);
            for &i in &data {
                if all || rng.next_u64().is_multiple_of(2) {
                    let mut l = line(&mut lines, i);
                    l.fields[5] = "0".to_owned();
                    lines[i] = Some(l);
                }
            }
        }
        6 => {
            for &i in &data {
                let mut l = line(&mut lines, i);
                if l.fields[1] == "1" {
                    l.set(5, 1e-30);
                }
                lines[i] = Some(l);
            }
        }
        7 => {
            let i = if rng.next_u64().is_multiple_of(2) {
                0
            } else {
                index(rng, raw.len())
            };
            let mut raw = raw;
            if let Some(l) = lines[i].take() {
                raw[i] = l.fields.join(" ");
            }
            raw[i] = format!("\u{feff}{}", raw[i]);
            return Some(join(&lines, &raw));
        }
        8 => {
            // A node's parent becomes one of its descendants (or itself).
            let i = any(rng);
            let j = data[(data.iter().position(|&k| k == i).unwrap_or(0) + index(rng, 20))
                .min(data.len() - 1)];
            let id = lines[j]
                .as_ref()
                .map(|l| l.fields[0].clone())
                .unwrap_or_default();
            let mut l = line(&mut lines, i);
            l.fields[6] = id;
            lines[i] = Some(l);
        }
        9 => {
            for _ in 0..1 + index(rng, 5) {
                let i = any(rng);
                lines[i] = None;
            }
            let mut raw = raw;
            for (l, r) in lines.iter().zip(raw.iter_mut()) {
                if l.is_none()
                    && !r.trim_start().starts_with('#')
                    && r.split_whitespace().count() >= 7
                {
                    r.clear();
                }
            }
            return Some(join(&lines, &raw));
        }
        10 => {
            let i = any(rng);
            let copy = lines[i]
                .as_ref()
                .map(|l| l.fields.join(" "))
                .unwrap_or_default();
            let mut text = join(&lines, &raw);
            text.push_str(&copy);
            text.push('\n');
            return Some(text);
        }
        11 => {
            let i = any(rng);
            let mut l = line(&mut lines, i);
            let k = index(rng, 7);
            l.fields[k] = pick(
                rng,
                &[
                    "NaN",
                    "inf",
                    "-inf",
                    "1e999",
                    "abc",
                    "0x10",
                    "1,5",
                    "--1",
                    "9223372036854775808",
                ],
            )
            .to_owned();
            if rng.next_u64().is_multiple_of(4) {
                l.fields[k] = "9".repeat(5000);
            }
            lines[i] = Some(l);
        }
        12 => {
            let text = join(&lines, &raw);
            let mut cut = index(rng, text.len());
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            return Some(text[..cut].to_owned());
        }
        13 => {
            // The whole cell again, ids shifted, as a second tree on the first.
            let shift = next_id(&lines, &data);
            let mut text = join(&lines, &raw);
            for &i in &data {
                let l = lines[i].as_ref().expect("a data line");
                let mut f = l.fields.clone();
                f[0] = (l.num(0) as i64 + shift).to_string();
                let parent = l.num(6) as i64;
                f[6] = if parent < 0 {
                    "-1".to_owned()
                } else {
                    (parent + shift).to_string()
                };
                text.push_str(&f.join(" "));
                text.push('\n');
            }
            return Some(text);
        }
        14 => {
            for &i in &data {
                let mut l = line(&mut lines, i);
                let r = l.num(5).abs().max(0.01);
                for k in 2..5 {
                    let v = l.num(k) + (rng.f64() - 0.5) * r;
                    l.set(k, v);
                }
                lines[i] = Some(l);
            }
        }
        _ => {
            let text = join(&lines, &raw);
            let ending = pick(rng, &["\r\n", "\r", "\n\n"]);
            return Some(text.replace('\n', ending));
        }
    }
    Some(join(&lines, &raw))
}

/// `k` children (10, 30 or 200) added to one sample, each a short segment of
/// two samples in its own direction.
fn star(lines: Vec<Option<Line>>, raw: Vec<String>, data: &[usize], rng: &mut Rng) -> String {
    let hub = lines[data[index(rng, data.len())]]
        .as_ref()
        .expect("a data line");
    let (id, x, y, z, r) = (
        hub.num(0) as i64,
        hub.num(2),
        hub.num(3),
        hub.num(4),
        hub.num(5),
    );
    let r = r.abs().max(0.1);
    let mut next = next_id(&lines, data);
    let mut text = join(&lines, &raw);
    let k = pick(rng, &[10usize, 30, 200]);
    for _ in 0..k {
        let d = rng.unit();
        let (a, b) = (next, next + 1);
        for (s, parent, reach) in [(a, id, 3.0), (b, a, 6.0)] {
            text.push_str(&format!(
                "{s} 3 {} {} {} {} {parent}\n",
                x + d.x * reach * r,
                y + d.y * reach * r,
                z + d.z * reach * r,
                0.3 * r
            ));
        }
        next += 2;
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    const CELL: &str =
        "# a cell\n1 1 0 0 0 5 -1\n2 3 10 0 0 1 1\n3 3 20 0 0 1 2\n4 3 20 10 0 1 3\n";

    #[test]
    fn every_kind_changes_the_file_and_the_same_seed_gives_the_same_text() {
        for kind in 0..KINDS.len() {
            let a = mutate(CELL, kind, &mut Rng::new(7)).expect("data lines");
            let b = mutate(CELL, kind, &mut Rng::new(7)).expect("data lines");
            assert_eq!(a, b, "{}", KINDS[kind]);
            assert_ne!(a, CELL, "{}", KINDS[kind]);
        }
        assert!(mutate("# only a comment\n", 0, &mut Rng::new(1)).is_none());
    }
}
