//! An exact solver for sparse linear assignment problems: the auction
//! algorithm with epsilon scaling (Bertsekas 1988; Bertsekas & Castanon
//! 1991) on integer costs.
//!
//! Sources bid for destinations; a bid raises the destination's price by
//! the bidder's margin between its best and second-best edge plus `eps`.
//! Every phase ends with a perfect matching satisfying eps-complementary
//! slackness, which is within `n * eps` of the optimum. Costs are multiplied
//! by `n + 1` and the last phase runs with `eps = 1`, so the result is an
//! exact minimum-cost perfect matching of the integer costs. Phases divide
//! `eps` by [`EPS_FACTOR`] and keep the prices of the previous phase.
//! Deterministic: sources are served first in, first out.

use super::BakeError;
use alloc::collections::VecDeque;
use alloc::vec;
use alloc::vec::Vec;

/// Divisor of epsilon between auction phases (Bertsekas recommends 4 to 10;
/// 6 was fastest on 64x64 retarget problems in our measurements).
pub const EPS_FACTOR: i64 = 6;

const NONE: u32 = u32::MAX;

/// A sparse cost graph of a square assignment problem: `size()` sources
/// and as many destinations, `0..size()` each.
pub trait SparseCosts {
    /// Number of sources (and of destinations).
    fn size(&self) -> usize;
    /// Calls `edge(destination, cost)` for every allowed destination of
    /// `source`. Must be deterministic; destinations must be `< size()`.
    fn for_each_edge(&self, source: usize, edge: impl FnMut(usize, u64));
}

/// A sparse cost graph stored row by row (compressed sparse rows).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SparseMatrix {
    starts: Vec<usize>,
    edges: Vec<(u32, u64)>,
}

impl SparseMatrix {
    /// Builds the graph of `size` sources from `(source, destination, cost)`
    /// triples (any order; edges of one source keep their relative order).
    /// Triples with a source or destination `>= size` are ignored.
    pub fn new(size: usize, triples: &[(u32, u32, u64)]) -> Self {
        let mut counts = vec![0usize; size + 1];
        let valid = |&&(s, d, _): &&(u32, u32, u64)| (s as usize) < size && (d as usize) < size;
        for &(s, _, _) in triples.iter().filter(valid) {
            counts[s as usize + 1] += 1;
        }
        for i in 0..size {
            counts[i + 1] += counts[i];
        }
        let mut fill = counts.clone();
        let mut edges = vec![(0u32, 0u64); counts[size]];
        for &(s, d, c) in triples.iter().filter(valid) {
            edges[fill[s as usize]] = (d, c);
            fill[s as usize] += 1;
        }
        SparseMatrix {
            starts: counts,
            edges,
        }
    }
}

impl SparseCosts for SparseMatrix {
    fn size(&self) -> usize {
        self.starts.len() - 1
    }
    fn for_each_edge(&self, source: usize, mut edge: impl FnMut(usize, u64)) {
        for &(d, c) in &self.edges[self.starts[source]..self.starts[source + 1]] {
            edge(d as usize, c);
        }
    }
}

/// A minimum-cost perfect matching.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Assignment {
    /// `destination[source]`: a permutation of `0..size`.
    pub destination: Vec<u32>,
    /// Sum of the costs of the chosen edges.
    pub cost: u64,
    /// Number of bids made over all phases (a measure of the work done).
    pub bids: u64,
}

/// Solves the assignment problem exactly.
///
/// # Errors
/// [`BakeError::CostRange`] if `max_cost * (size + 1)^2` does not fit the
/// solver's `i64` prices with margin; [`BakeError::Infeasible`] if a source
/// has no edge, or no perfect matching exists (detected when a price exceeds
/// a bound that feasible problems never reach).
pub fn solve_assignment<C: SparseCosts>(costs: &C) -> Result<Assignment, BakeError> {
    let n = costs.size();
    if n == 0 {
        return Ok(Assignment {
            destination: Vec::new(),
            cost: 0,
            bids: 0,
        });
    }
    let mut max_cost = 0u64;
    for s in 0..n {
        let mut degree = 0;
        costs.for_each_edge(s, |_, c| {
            max_cost = max_cost.max(c);
            degree += 1;
        });
        if degree == 0 {
            return Err(BakeError::Infeasible);
        }
    }
    let range = BakeError::CostRange { max_cost, size: n };
    let scale = n as i64 + 1;
    let cmax = i64::try_from(max_cost)
        .ok()
        .and_then(|c| c.checked_mul(scale))
        .ok_or(range)?;
    let eps0 = (cmax / EPS_FACTOR).max(1);
    let mut phases = 1i64;
    let mut e = eps0;
    while e > 1 {
        e = (e / EPS_FACTOR).max(1);
        phases += 1;
    }
    // Prices never exceed this in a feasible problem: each phase raises any
    // price by at most about n * (cmax + eps); doubled for margin.
    let bound = cmax
        .checked_add(eps0)
        .and_then(|v| v.checked_mul(scale))
        .and_then(|v| v.checked_mul(2 * phases))
        .filter(|&b| b < i64::MAX / 4)
        .ok_or(range)?;

    let mut prices = vec![0i64; n];
    let mut owner = vec![NONE; n];
    let mut destination = vec![NONE; n];
    let mut queue: VecDeque<u32> = VecDeque::with_capacity(n);
    let mut bids = 0u64;
    let mut eps = eps0;
    loop {
        owner.fill(NONE);
        destination.fill(NONE);
        queue.extend(0..n as u32);
        while let Some(i) = queue.pop_front() {
            let (mut best, mut second, mut target) = (i64::MAX, i64::MAX, usize::MAX);
            costs.for_each_edge(i as usize, |j, c| {
                let v = c as i64 * scale + prices[j];
                if v < best {
                    second = best;
                    best = v;
                    target = j;
                } else if v < second {
                    second = v;
                }
            });
            if target >= n {
                return Err(BakeError::Infeasible);
            }
            let margin = if second == i64::MAX {
                cmax + eps
            } else {
                second - best
            };
            prices[target] += margin + eps;
            if prices[target] > bound {
                return Err(BakeError::Infeasible);
            }
            bids += 1;
            let previous = core::mem::replace(&mut owner[target], i);
            destination[i as usize] = target as u32;
            if previous != NONE {
                destination[previous as usize] = NONE;
                queue.push_back(previous);
            }
        }
        if eps == 1 {
            break;
        }
        eps = (eps / EPS_FACTOR).max(1);
    }
    let mut cost = 0u64;
    for (s, &d) in destination.iter().enumerate() {
        let mut c_sd = u64::MAX;
        costs.for_each_edge(s, |j, c| {
            if j == d as usize {
                c_sd = c_sd.min(c);
            }
        });
        cost += c_sd;
    }
    Ok(Assignment {
        destination,
        cost,
        bids,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bake::SplitMix64;

    /// Minimum over all permutations (Heap's algorithm); `None` if none is allowed.
    fn brute_force(n: usize, cost: &[Option<u64>]) -> Option<u64> {
        let mut perm: Vec<usize> = (0..n).collect();
        let eval = |p: &[usize]| -> Option<u64> { (0..n).map(|s| cost[s * n + p[s]]).sum() };
        let mut best = eval(&perm);
        let mut c = vec![0usize; n];
        let mut i = 0;
        while i < n {
            if c[i] < i {
                if i % 2 == 0 {
                    perm.swap(0, i);
                } else {
                    perm.swap(c[i], i);
                }
                if let Some(v) = eval(&perm) {
                    best = Some(best.map_or(v, |b: u64| b.min(v)));
                }
                c[i] += 1;
                i = 0;
            } else {
                c[i] = 0;
                i += 1;
            }
        }
        best
    }

    #[test]
    fn matches_brute_force_on_random_sparse_problems() {
        let mut rng = SplitMix64::new(11);
        for trial in 0..300 {
            let n = 1 + rng.below(7) as usize;
            let max = [3u64, 100, 1 << 20][trial % 3];
            // Keep the identity so a perfect matching exists, plus random edges.
            let mut cost = vec![None; n * n];
            let mut triples = Vec::new();
            for s in 0..n {
                for d in 0..n {
                    if s == d || rng.below(2) == 0 {
                        let c = rng.below(max + 1);
                        cost[s * n + d] = Some(c);
                        triples.push((s as u32, d as u32, c));
                    }
                }
            }
            let m = SparseMatrix::new(n, &triples);
            let a = solve_assignment(&m).unwrap();
            let mut seen = vec![false; n];
            for (s, &d) in a.destination.iter().enumerate() {
                assert!(cost[s * n + d as usize].is_some());
                assert!(!core::mem::replace(&mut seen[d as usize], true));
            }
            assert_eq!(Some(a.cost), brute_force(n, &cost), "trial {trial}");
        }
    }

    #[test]
    fn infeasible_problems_are_errors() {
        // Sources 0 and 1 both only reach destination 0.
        let m = SparseMatrix::new(2, &[(0, 0, 1), (1, 0, 2)]);
        assert_eq!(solve_assignment(&m), Err(BakeError::Infeasible));
        // A source without edges.
        let m = SparseMatrix::new(2, &[(0, 0, 1), (0, 1, 2)]);
        assert_eq!(solve_assignment(&m), Err(BakeError::Infeasible));
        // Costs too large for the scaled integer prices.
        let m = SparseMatrix::new(2, &[(0, 0, u64::MAX / 2), (1, 1, 0)]);
        assert!(matches!(solve_assignment(&m), Err(BakeError::CostRange { .. })));
        assert_eq!(
            solve_assignment(&SparseMatrix::new(0, &[]))
                .unwrap()
                .destination
                .len(),
            0
        );
    }
}
