//! A hierarchical min/max cache for void-and-cluster: the largest energy
//! among the ones ("tightest cluster") and the smallest among the zeros
//! ("largest void"), ties broken by the lowest texel index.
//!
//! # Keys
//!
//! The caller keeps one `i32` **key** per texel: its energy (`0..2^30`),
//! plus [`ONE_BIAS`] if the texel is a one. Then the largest key is the
//! tightest cluster (if it is at least `ONE_BIAS`) and the smallest key the
//! largest void (if it is below `ONE_BIAS`): one branch-free min/max serves
//! both queries.
//!
//! Texels are grouped 16 to a node, nodes 16 to a parent, up to one root.
//! After a splat changes a few hundred keys, only the touched nodes and
//! their ancestors are recomputed (`O(touched * 16 + log16 n)` instead of a
//! full `O(n)` scan per step).

use alloc::vec;
use alloc::vec::Vec;

/// Added to the key of a one; energies stay below it.
pub(crate) const ONE_BIAS: i32 = 1 << 30;

const FAN_LOG2: u32 = 4;
const FAN: usize = 1 << FAN_LOG2;

/// Position of the first minimum of a non-empty slice.
#[inline]
fn first_min(v: &[i32]) -> usize {
    let lo = v.iter().copied().fold(i32::MAX, i32::min);
    v.iter().position(|&x| x == lo).unwrap_or(0)
}

/// Position of the first maximum of a non-empty slice.
#[inline]
fn first_max(v: &[i32]) -> usize {
    let hi = v.iter().copied().fold(i32::MIN, i32::max);
    v.iter().position(|&x| x == hi).unwrap_or(0)
}

#[derive(Clone, Debug)]
struct Level {
    mins: Vec<i32>,
    min_at: Vec<u32>,
    maxs: Vec<i32>,
    max_at: Vec<u32>,
    dirty: Vec<u32>,
    flagged: Vec<bool>,
}

impl Level {
    fn new(count: usize) -> Self {
        Level {
            mins: vec![0; count],
            min_at: vec![0; count],
            maxs: vec![0; count],
            max_at: vec![0; count],
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

/// The cache over `n` keys. Call [`touch`](Self::touch) for every texel
/// whose key changed, then [`refresh`](Self::refresh) before querying.
#[derive(Clone, Debug)]
pub(crate) struct Extrema {
    levels: Vec<Level>,
    track_min: bool,
    track_max: bool,
}

/// Which single query an [`Extrema`] keeps up to date once restricted
/// (a new cache keeps both).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Track {
    /// Only [`Extrema::tightest_cluster`] (removing ones).
    Clusters,
    /// Only [`Extrema::largest_void`] (adding ones).
    Voids,
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
        Extrema {
            levels,
            track_min: true,
            track_max: true,
        }
    }

    /// Restricts the queries kept up to date (halves the work of a
    /// refresh). Call on a clean (refreshed) cache; the untracked query
    /// must not be used afterwards.
    pub(crate) fn track(&mut self, track: Track) {
        self.track_min = track != Track::Clusters;
        self.track_max = track != Track::Voids;
    }

    /// Marks texel `i` as changed.
    #[inline]
    pub(crate) fn touch(&mut self, i: usize) {
        self.levels[0].mark(i >> FAN_LOG2);
    }

    /// Marks texels `start..end` (`start < end`) as changed.
    #[inline]
    pub(crate) fn touch_range(&mut self, start: usize, end: usize) {
        for node in (start >> FAN_LOG2)..=((end - 1) >> FAN_LOG2) {
            self.levels[0].mark(node);
        }
    }

    /// Recomputes every node above a touched texel.
    pub(crate) fn refresh(&mut self, keys: &[i32]) {
        for level in 0..self.levels.len() {
            let (below, rest) = self.levels.split_at_mut(level);
            let (this, above) = rest.split_first_mut().expect("level exists");
            let mut dirty = core::mem::take(&mut this.dirty);
            for &node in &dirty {
                let node = node as usize;
                let start = node << FAN_LOG2;
                if let Some(children) = below.last() {
                    let end = (start + FAN).min(children.mins.len());
                    if self.track_min {
                        let lo = first_min(&children.mins[start..end]);
                        this.mins[node] = children.mins[start + lo];
                        this.min_at[node] = children.min_at[start + lo];
                    }
                    if self.track_max {
                        let hi = first_max(&children.maxs[start..end]);
                        this.maxs[node] = children.maxs[start + hi];
                        this.max_at[node] = children.max_at[start + hi];
                    }
                } else {
                    let end = (start + FAN).min(keys.len());
                    let v = &keys[start..end];
                    if self.track_min {
                        let lo = first_min(v);
                        this.mins[node] = v[lo];
                        this.min_at[node] = (start + lo) as u32;
                    }
                    if self.track_max {
                        let hi = first_max(v);
                        this.maxs[node] = v[hi];
                        this.max_at[node] = (start + hi) as u32;
                    }
                }
                this.flagged[node] = false;
                if let Some(parent) = above.first_mut() {
                    parent.mark(node >> FAN_LOG2);
                }
            }
            dirty.clear();
            this.dirty = dirty;
        }
    }

    fn root(&self) -> &Level {
        &self.levels[self.levels.len() - 1]
    }

    /// Index of the one with the largest key (lowest index on ties), if any.
    pub(crate) fn tightest_cluster(&self) -> Option<usize> {
        let r = self.root();
        (r.maxs[0] >= ONE_BIAS).then_some(r.max_at[0] as usize)
    }

    /// Index of the zero with the smallest key (lowest index on ties), if any.
    pub(crate) fn largest_void(&self) -> Option<usize> {
        let r = self.root();
        (r.mins[0] < ONE_BIAS).then_some(r.min_at[0] as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Checks the cache against a plain scan after random updates.
    #[test]
    fn matches_a_linear_scan() {
        let mut rng = super::super::SplitMix64::new(3);
        let draw = |rng: &mut super::super::SplitMix64| {
            rng.below(50) as i32 + if rng.below(3) == 0 { ONE_BIAS } else { 0 }
        };
        for n in [1usize, 5, 16, 17, 255, 256, 257, 4099] {
            let mut keys: Vec<i32> = (0..n).map(|_| draw(&mut rng)).collect();
            let mut ex = Extrema::new(n);
            ex.refresh(&keys);
            let (mut clusters, mut voids) = (ex.clone(), ex.clone());
            clusters.track(Track::Clusters);
            voids.track(Track::Voids);
            for round in 0..200 {
                if round > 0 {
                    for _ in 0..rng.below(20) {
                        let i = rng.below(n as u64) as usize;
                        keys[i] = draw(&mut rng);
                        if rng.below(2) == 0 {
                            ex.touch(i);
                            clusters.touch(i);
                            voids.touch(i);
                        } else {
                            let end = (i + 1 + rng.below(40) as usize).min(n);
                            ex.touch_range(i, end);
                            clusters.touch_range(i, end);
                            voids.touch_range(i, end);
                        }
                    }
                }
                ex.refresh(&keys);
                clusters.refresh(&keys);
                voids.refresh(&keys);
                let ones = |i: &usize| keys[*i] >= ONE_BIAS;
                let scan_max = (0..n).filter(ones).fold(None, |b: Option<usize>, i| match b {
                    Some(j) if keys[j] >= keys[i] => Some(j),
                    _ => Some(i),
                });
                let scan_min = (0..n)
                    .filter(|i| !ones(i))
                    .fold(None, |b: Option<usize>, i| match b {
                        Some(j) if keys[j] <= keys[i] => Some(j),
                        _ => Some(i),
                    });
                assert_eq!(ex.tightest_cluster(), scan_max, "n {n} round {round}");
                assert_eq!(ex.largest_void(), scan_min, "n {n} round {round}");
                assert_eq!(clusters.tightest_cluster(), scan_max, "n {n} round {round}");
                assert_eq!(voids.largest_void(), scan_min, "n {n} round {round}");
            }
        }
    }
}
