//! Comparing refined meshes whose vertices are numbered differently (the patch path and the
//! reference driver number their outputs each their own way).

/// Largest distance (max norm) from each point of `a` to the nearest point of `b` not yet
/// paired: a bijection between the two point sets, so that a small result means the same set.
/// Infinite when the counts differ or a point of `a` has no unpaired point of `b` within 1e-9
/// in x.
pub fn same_points(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    // Candidates by x: a window of width 2e-9 around each point's x.
    let mut order: Vec<usize> = (0..b.len()).collect();
    order.sort_by(|&i, &j| b[i][0].total_cmp(&b[j][0]));
    let xs: Vec<f64> = order.iter().map(|&i| b[i][0]).collect();
    let mut used = vec![false; b.len()];
    let mut worst = 0.0f64;
    for p in a {
        let start = xs.partition_point(|&x| x < p[0] - 1e-9);
        let Some((j, d)) = order[start..]
            .iter()
            .take_while(|&&j| b[j][0] <= p[0] + 1e-9)
            .filter(|&&j| !used[j]) // coincident points (self-intersecting immersions) pair up
            .map(|&j| {
                (
                    j,
                    (0..3).map(|c| (p[c] - b[j][c]).abs()).fold(0.0, f64::max),
                )
            })
            .min_by(|x, y| x.1.total_cmp(&y.1))
        else {
            return f64::INFINITY;
        };
        used[j] = true;
        worst = worst.max(d);
    }
    worst
}
