//! Pareto front of points with two costs, both to be minimised (pass a
//! negated value for a quantity to maximise, e.g. rays/cycle).

/// Indices of the points no other point dominates, sorted by (x, y, index).
/// `a` dominates `b` when a.x <= b.x and a.y <= b.y with one strict; equal
/// points do not dominate each other, so both stay on the front.
/// Panics on NaN: callers leave out points that lack a coordinate.
pub fn front(points: &[(f64, f64)]) -> Vec<usize> {
    assert!(
        points.iter().all(|(x, y)| !x.is_nan() && !y.is_nan()),
        "pareto::front: NaN coordinate"
    );
    let dominates =
        |a: (f64, f64), b: (f64, f64)| a.0 <= b.0 && a.1 <= b.1 && (a.0 < b.0 || a.1 < b.1);
    let mut out: Vec<usize> = (0..points.len())
        .filter(|&i| !points.iter().any(|&p| dominates(p, points[i])))
        .collect();
    out.sort_by(|&a, &b| points[a].partial_cmp(&points[b]).unwrap().then(a.cmp(&b)));
    out
}

#[cfg(test)]
mod tests {
    use super::front;
    use rand::{Rng, SeedableRng};

    #[test]
    fn keeps_the_staircase_and_drops_dominated_points() {
        // (error, area)
        let p = [
            (5.0, 1.0),
            (0.0, 10.0),
            (1.0, 4.0),
            (2.0, 4.0),
            (1.0, 6.0),
            (0.0, 12.0),
            (6.0, 1.0),
        ];
        assert_eq!(front(&p), vec![1, 2, 0]);
    }

    #[test]
    fn equal_points_both_stay_and_single_or_empty_sets_work() {
        assert_eq!(front(&[(1.0, 1.0), (1.0, 1.0), (2.0, 2.0)]), vec![0, 1]);
        assert_eq!(front(&[(3.0, -1.0)]), vec![0]);
        assert!(front(&[]).is_empty());
    }

    #[test]
    fn maximising_by_negation() {
        // (error, -rays per cycle): the fastest zero-error point wins.
        let p = [(0.0, -0.5), (0.0, -0.7), (3.0, -0.9), (3.0, -0.8)];
        assert_eq!(front(&p), vec![1, 2]);
    }

    #[test]
    fn matches_brute_force_definition_on_random_sets() {
        let seed = 61;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        for _ in 0..200 {
            let n = rng.gen_range(1..30);
            let p: Vec<(f64, f64)> = (0..n)
                .map(|_| (rng.gen_range(0..6) as f64, rng.gen_range(0..6) as f64))
                .collect();
            let f = front(&p);
            for i in 0..n {
                let dominated = p
                    .iter()
                    .any(|q| q.0 <= p[i].0 && q.1 <= p[i].1 && q != &p[i]);
                assert_eq!(
                    f.contains(&i),
                    !dominated,
                    "seed {seed}: point {i} of {p:?}"
                );
            }
            // Along the front, x rises and y falls.
            for w in f.windows(2) {
                assert!(
                    p[w[0]].0 <= p[w[1]].0 && p[w[0]].1 >= p[w[1]].1,
                    "seed {seed}: {p:?}"
                );
            }
        }
    }
}
