//! Disjoint sets with a numbering by first appearance, and the connected
//! components of a triangle soup that they give.

/// Disjoint sets over `0..n` (path halving, smaller root wins, so the result
/// does not depend on the order of unions).
pub struct UnionFind(Vec<u32>);

impl UnionFind {
    /// `n` sets of one item each.
    pub fn new(n: usize) -> Self {
        UnionFind((0..n as u32).collect())
    }
    /// The root of item `i`'s set.
    pub fn find(&mut self, mut i: u32) -> u32 {
        while self.0[i as usize] != i {
            let next = self.0[i as usize];
            self.0[i as usize] = self.0[next as usize];
            i = next;
        }
        i
    }
    /// Joins the sets of items `a` and `b`.
    pub fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        self.link(ra, rb);
    }
    /// Joins the sets of the roots `ra` and `rb`; the root of the whole.
    pub fn link(&mut self, ra: u32, rb: u32) -> u32 {
        if ra != rb {
            self.0[ra.max(rb) as usize] = ra.min(rb);
        }
        ra.min(rb)
    }
    /// The sets numbered in the order [`Numbering::number`] first meets
    /// them, in the sets' own array: no second array of the items' size.
    pub fn into_numbering(mut self) -> Numbering {
        // A set is joined under its lowest item, so an item's parent comes
        // before it, and one pass in order points every item at its root.
        for i in 0..self.0.len() {
            let parent = self.0[i] as usize;
            self.0[i] = self.0[parent];
        }
        assert!(self.0.len() < NUMBERED as usize, "too many items");
        Numbering {
            slots: self.0,
            next: 0,
        }
    }
}

/// Marks a root's slot that holds its set's number rather than itself.
const NUMBERED: u32 = 1 << 31;

/// Set numbers in order of first appearance ([`UnionFind::into_numbering`]).
pub struct Numbering {
    /// A numbered root's slot holds its number (marked); any other item's,
    /// its root.
    slots: Vec<u32>,
    next: u32,
}

impl Numbering {
    /// The number of item `i`'s set, the next one if it has none yet.
    pub fn number(&mut self, i: u32) -> u32 {
        let r = match self.slots[i as usize] {
            v if v & NUMBERED != 0 => return v & !NUMBERED,
            v => v as usize,
        };
        if self.slots[r] & NUMBERED == 0 {
            self.slots[r] = self.fresh() | NUMBERED;
        }
        self.slots[r] & !NUMBERED
    }

    /// A number for something in no set.
    pub fn fresh(&mut self) -> u32 {
        self.next += 1;
        self.next - 1
    }

    /// How many numbers were given.
    pub fn count(&self) -> usize {
        self.next as usize
    }
}

/// The connected component (by shared vertices) of every face, numbered from 0
/// in order of first appearance.
pub fn face_components(faces: &[[u32; 3]], n_vertices: usize) -> Vec<u32> {
    let mut uf = UnionFind::new(n_vertices);
    // The last face's corners are all in the set of `last_root` (still a
    // root: nothing was joined since). Faces come in strips that share two
    // corners with the face before: those need no find.
    let (mut last, mut last_root) = ([u32::MAX; 3], u32::MAX);
    for f in faces {
        let first_in_last = last.contains(&f[0]);
        // The first corner's root carried on: a find per other corner.
        let mut root = if first_in_last {
            last_root
        } else {
            uf.find(f[0])
        };
        for &v in &f[1..] {
            if !(first_in_last && last.contains(&v)) {
                let rv = uf.find(v);
                root = uf.link(root, rv);
            }
        }
        (last, last_root) = (*f, root);
    }
    let mut numbering = uf.into_numbering();
    faces.iter().map(|f| numbering.number(f[0])).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_are_numbered_by_first_appearance() {
        let mut uf = UnionFind::new(7);
        uf.union(5, 2);
        uf.union(6, 0);
        uf.union(2, 4);
        let mut n = uf.into_numbering();
        // Sets {2, 4, 5}, {0, 6}, {1}, {3}, met in the order 4, 1, 6, ...
        assert_eq!([4, 1, 6, 5, 0, 2].map(|i| n.number(i)), [0, 1, 2, 0, 2, 0]);
        assert_eq!(n.fresh(), 3);
        assert_eq!(n.number(3), 4);
        assert_eq!(n.count(), 5);
    }

    #[test]
    fn faces_joined_through_corners_are_one_component() {
        // Two strips of two triangles each, the second met in two halves.
        let faces = [[0, 1, 2], [1, 3, 2], [4, 5, 6], [2, 3, 0], [5, 7, 6]];
        assert_eq!(face_components(&faces, 8), vec![0, 0, 1, 0, 1]);
    }
}
