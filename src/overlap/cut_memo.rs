//! The pieces of cut faces, remembered by what each face was cut from, so
//! that cutting a cluster again after a nudge re-triangulates only the faces
//! the nudge changed.
//!
//! When a cut is refused, the overlap pass nudges the few vertices at fault
//! and cuts the whole cluster again ([`crate::overlap`]). A cluster can hold
//! tens of thousands of crossing pairs (crowded fillers), and
//! re-triangulating all its faces for a nudge of a few dozen vertices would
//! be most of the re-cut's time.
//!
//! A face's pieces are a function of its inputs alone: the exact coordinates
//! of its corners, those of the new vertices around and inside it (in the
//! plane it is triangulated in, which its corners choose) in their order,
//! and the cut segments between them as local numbers. The inputs are taken
//! once the face's triple points are made (new vertices where two cut
//! segments cross inside it), so they include them. A face whose inputs are
//! the same as the last time takes its pieces from then, renumbered to the
//! vertices of this cut (their numbers change when a pair before them
//! changes). Only successes are remembered: a face refused is cut again.

use std::ops::Range;

use crate::kernel::hash::FastMap;

/// Remembered pieces: per face, its inputs (as bits) and its pieces as
/// local numbers, stored flat.
#[derive(Debug, Default, Clone)]
pub struct Memo {
    inputs: Vec<u64>,
    pieces: Vec<[u32; 3]>,
    at: FastMap<u32, (Range<u32>, Range<u32>)>,
}

impl Memo {
    /// The pieces (local numbers) of face `f` if it was cut from `inputs`.
    pub fn get(&self, f: u32, inputs: &[u64]) -> Option<&[[u32; 3]]> {
        let (i, p) = self.at.get(&f)?;
        (self.inputs[i.start as usize..i.end as usize] == *inputs)
            .then(|| &self.pieces[p.start as usize..p.end as usize])
    }

    /// Remembers that face `f`, cut from `inputs`, gave `pieces`.
    pub fn put(&mut self, f: u32, inputs: &[u64], pieces: impl IntoIterator<Item = [u32; 3]>) {
        let i = self.inputs.len() as u32..(self.inputs.len() + inputs.len()) as u32;
        self.inputs.extend_from_slice(inputs);
        let start = self.pieces.len() as u32;
        self.pieces.extend(pieces);
        self.at.insert(f, (i, start..self.pieces.len() as u32));
    }

    /// Adds what `other` remembers (of other faces).
    pub fn absorb(&mut self, other: Memo) {
        let (di, dp) = (self.inputs.len() as u32, self.pieces.len() as u32);
        self.inputs.extend_from_slice(&other.inputs);
        self.pieces.extend_from_slice(&other.pieces);
        self.at.extend(
            other
                .at
                .into_iter()
                .map(|(f, (i, p))| (f, (i.start + di..i.end + di, p.start + dp..p.end + dp))),
        );
    }

    /// The same memo with each remembered piece's corners turned once
    /// (the same triangle, other numbers): a test can tell its pieces from
    /// fresh ones.
    #[cfg(test)]
    pub(crate) fn turned(&self) -> Memo {
        let mut m = self.clone();
        for t in &mut m.pieces {
            *t = [t[1], t[2], t[0]];
        }
        m
    }

    /// Whether nothing is remembered.
    pub fn is_empty(&self) -> bool {
        self.at.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_face_gets_its_pieces_back_only_for_the_same_inputs() {
        let mut a = Memo::default();
        a.put(7, &[1, 2, 3], [[0, 1, 2], [0, 2, 3]]);
        let mut b = Memo::default();
        b.put(9, &[4], [[2, 1, 0]]);
        a.absorb(b);
        assert_eq!(a.get(7, &[1, 2, 3]), Some(&[[0, 1, 2], [0, 2, 3]][..]));
        assert_eq!(a.get(7, &[1, 2, 4]), None);
        assert_eq!(a.get(7, &[1, 2]), None);
        assert_eq!(a.get(9, &[4]), Some(&[[2, 1, 0]][..]));
        assert_eq!(a.get(8, &[4]), None);
        assert!(!a.is_empty() && Memo::default().is_empty());
    }
}
