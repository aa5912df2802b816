//! A hierarchical min/max cache for void-and-cluster: the largest energy
//! among the ones ("tightest cluster") and the smallest among the zeros
//! ("largest void"), ties broken by the lowest texel index.
//!
//! Texels are grouped 16 to a node, nodes 16 to a parent, up to one root.
//! After a splat changes a few hundred energies, only the touched nodes and
//! their ancestors are recomputed (`O(touched * 16 + log16 n)` instead of a
//! full `O(n)` scan per step).

use alloc::vec;
use alloc::vec::Vec;

const FAN_LOG2: u32 = 4;
const FAN: usize = 1 << FAN_LOG2;
const NONE: u32 = u32::MAX;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Node {
    max_one: i32,
    max_index: u32,
    min_zero: i32,
    min_index: u32,
}

const EMPTY: Node = Node {
    max_one: i32::MIN,
    max_index: NONE,
    min_zero: i32::MAX,
    min_index: NONE,
};

impl Node {
    /// Merges `other`, which covers higher indices than `self`.
    #[inline]
    fn merge(&mut self, other: &Node) {
        if other.max_index != NONE && (self.max_index == NONE || other.max_one > self.max_one) {
            self.max_one = other.max_one;
            self.max_index = other.max_index;
        }
        if other.min_index != NONE && (self.min_index == NONE || other.min_zero < self.min_zero) {
            self.min_zero = other.min_zero;
            self.min_index = other.min_index;
        }
    }
}

#[derive(Clone, Debug)]
struct Level {
    nodes: Vec<Node>,
    dirty: Vec<u32>,
    flagged: Vec<bool>,
}

impl Level {
    fn new(count: usize) -> Self {
        Level {
            nodes: vec![EMPTY; count],
            dirty: (0..count as u32).collect(),
            flagged: vec![true; count],
        }
    }
    #[inline]
    fn mark(&mut self, node: usize) {
        if !self.flagged[node] {
            self.flagged[node] = true;
            self.dirty.push(node as u32);
        }
    }
}

/// The cache over `n` texels. Call [`touch`](Self::touch) for every texel
/// whose energy or membership changed, then [`refresh`](Self::refresh)
/// before querying.
#[derive(Clone, Debug)]
pub(crate) struct Extrema {
    levels: Vec<Level>,
}

impl Extrema {
    /// A cache over `n >= 1` texels, all dirty.
    pub(crate) fn new(n: usize) -> Self {
        let mut levels = Vec::new();
        let mut count = n;
        loop {
            count = count.div_ceil(FAN);
            levels.push(Level::new(count));
            if count <= 1 {
                break;
            }
        }
        Extrema { levels }
    }

    /// Marks texel `i` as changed.
    #[inline]
    pub(crate) fn touch(&mut self, i: usize) {
        self.levels[0].mark(i >> FAN_LOG2);
    }

    /// Recomputes every node above a touched texel.
    pub(crate) fn refresh(&mut self, energy: &[i32], ones: &[bool]) {
        let mut level0 = core::mem::take(&mut self.levels[0].dirty);
        for &node in &level0 {
            let node = node as usize;
            let start = node << FAN_LOG2;
            let end = (start + FAN).min(energy.len());
            let mut acc = EMPTY;
            for i in start..end {
                let e = energy[i];
                if ones[i] {
                    if acc.max_index == NONE || e > acc.max_one {
                        acc.max_one = e;
                        acc.max_index = i as u32;
                    }
                } else if acc.min_index == NONE || e < acc.min_zero {
                    acc.min_zero = e;
                    acc.min_index = i as u32;
                }
            }
            let l = &mut self.levels[0];
            l.nodes[node] = acc;
            l.flagged[node] = false;
            if let Some(parent) = self.levels.get_mut(1) {
                parent.mark(node >> FAN_LOG2);
            }
        }
        level0.clear();
        self.levels[0].dirty = level0;
        for level in 1..self.levels.len() {
            let (below, rest) = self.levels.split_at_mut(level);
            let children = &below[level - 1].nodes;
            let (this, above) = rest.split_first_mut().expect("level exists");
            let mut dirty = core::mem::take(&mut this.dirty);
            for &node in &dirty {
                let node = node as usize;
                let start = node << FAN_LOG2;
                let end = (start + FAN).min(children.len());
                let mut acc = EMPTY;
                for child in &children[start..end] {
                    acc.merge(child);
                }
                this.nodes[node] = acc;
                this.flagged[node] = false;
                if let Some(parent) = above.first_mut() {
                    parent.mark(node >> FAN_LOG2);
                }
            }
            dirty.clear();
            this.dirty = dirty;
        }
    }

    fn root(&self) -> &Node {
        &self.levels[self.levels.len() - 1].nodes[0]
    }

    /// Index of the one with the largest energy (lowest index on ties), if any.
    pub(crate) fn tightest_cluster(&self) -> Option<usize> {
        let r = self.root();
        (r.max_index != NONE).then_some(r.max_index as usize)
    }

    /// Index of the zero with the smallest energy (lowest index on ties), if any.
    pub(crate) fn largest_void(&self) -> Option<usize> {
        let r = self.root();
        (r.min_index != NONE).then_some(r.min_index as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Checks the cache against a plain scan after random updates.
    #[test]
    fn matches_a_linear_scan() {
        let mut rng = super::super::SplitMix64::new(3);
        for n in [1usize, 5, 16, 17, 255, 256, 257, 4099] {
            let mut energy: Vec<i32> = (0..n).map(|_| rng.below(50) as i32).collect();
            let mut ones: Vec<bool> = (0..n).map(|_| rng.below(3) == 0).collect();
            let mut ex = Extrema::new(n);
            for round in 0..200 {
                if round > 0 {
                    for _ in 0..rng.below(20) {
                        let i = rng.below(n as u64) as usize;
                        energy[i] = rng.below(50) as i32;
                        ones[i] = rng.below(3) == 0;
                        ex.touch(i);
                    }
                }
                ex.refresh(&energy, &ones);
                let scan_max = (0..n)
                    .filter(|&i| ones[i])
                    .fold(None, |b: Option<usize>, i| match b {
                        Some(j) if energy[j] >= energy[i] => Some(j),
                        _ => Some(i),
                    });
                let scan_min = (0..n)
                    .filter(|&i| !ones[i])
                    .fold(None, |b: Option<usize>, i| match b {
                        Some(j) if energy[j] <= energy[i] => Some(j),
                        _ => Some(i),
                    });
                assert_eq!(ex.tightest_cluster(), scan_max, "n {n} round {round}");
                assert_eq!(ex.largest_void(), scan_min, "n {n} round {round}");
            }
        }
    }
}
