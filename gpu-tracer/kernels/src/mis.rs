//! Multiple importance sampling: how the tracer weighs two strategies that
//! can produce the same path (next-event estimation against BSDF sampling,
//! environment-map sampling against BSDF sampling).

/// Power heuristic weight `a^2 / (a^2 + b^2)` of the strategy with density
/// `a` against one with density `b` (both `>= 0`); 0 when `a == 0`, and
/// free of overflow for large densities.
#[inline]
pub fn power_heuristic(a: f32, b: f32) -> f32 {
    if a > 0.0 {
        let r = b / a;
        1.0 / (1.0 + r * r)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_heuristic_weights_sum_to_one() {
        for (a, b) in [(1.0, 1.0), (0.3, 2.0), (1e30, 1e-30), (5.0, 0.0)] {
            let s = power_heuristic(a, b) + power_heuristic(b, a);
            assert!((s - 1.0).abs() < 1e-6, "{a} {b}: {s}");
        }
        assert_eq!(power_heuristic(0.0, 1.0), 0.0);
        assert_eq!(power_heuristic(f32::INFINITY, 1.0), 1.0);
    }
}
