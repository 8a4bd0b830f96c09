//! The rate sticks' reference data (seed 000 §5.1, Fig. 3): the LLNL
//! ANFO-K1 measurements and seed 000's own computed points, as digitised
//! for the blastFoam rate-stick validation, and the least-squares parabola
//! in 1/R that summarises the measurements (E-RATESTICK and
//! E-RATESTICK-RZ compare their detonation speeds with it).

/// The LLNL ANFO-K1 rate-stick measurements, (1/R in 1/mm, D in m/s): the
/// experimental points of seed 000 Fig. 3 (P. C. Souers, S. Anderson,
/// J. Mercer, E. McGuire, P. Vitello, "JWL++: a simple reactive flow code
/// package for detonation", Propellants, Explosives, Pyrotechnics 25 (2000)
/// 54–58), as digitised from that figure for the blastFoam rate-stick
/// validation (`validation/blastFoam/rateStick/validation/validationData/
/// experimental_LNLL.csv`, github.com/synthetik-technologies/blastfoam).
/// Read off a plot: tens of m/s of reading error.
pub const LLNL_ANFO_K1: [(f64, f64); 17] = [
    (0.000404, 5890.0),
    (0.02306, 5617.0),
    (0.02569, 5647.0),
    (0.03600, 5463.0),
    (0.04166, 5383.0),
    (0.06007, 5379.0),
    (0.05299, 5359.0),
    (0.05885, 5230.0),
    (0.05885, 5080.0),
    (0.09162, 4533.0),
    (0.09425, 4533.0),
    (0.09769, 4648.0),
    (0.09748, 4742.0),
    (0.1181, 4394.0),
    (0.1183, 4324.0),
    (0.1466, 3757.0),
    (0.1539, 3672.0),
];

/// Seed 000 Fig. 3's computed points (ICE with JWL++, 1/R in 1/mm, D in
/// m/s) from the same digitisation (`guilkey_et_al_2007.csv`), which keeps
/// one of the figure's three resolutions without saying which.
pub const SEED_000_FIG3: [(f64, f64); 5] = [
    (0.0, 5760.0),
    (0.05, 5404.0),
    (0.08, 4906.0),
    (0.125, 4624.0),
    (0.16667, 4087.0),
];

/// Least-squares parabola D = c₀ + c₁x + c₂x² through `points` (x, D),
/// from the 3 × 3 normal equations by Cramer's rule; `None` when they are
/// singular (fewer than three distinct x).
pub fn quadratic_fit(points: &[(f64, f64)]) -> Option<[f64; 3]> {
    let mut s = [0.0; 5];
    let mut t = [0.0; 3];
    for &(x, y) in points {
        let mut xp = 1.0;
        for (k, sk) in s.iter_mut().enumerate() {
            *sk += xp;
            if k < 3 {
                t[k] += xp * y;
            }
            xp *= x;
        }
    }
    let a = [[s[0], s[1], s[2]], [s[1], s[2], s[3]], [s[2], s[3], s[4]]];
    let det3 = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let mut xs: Vec<f64> = points.iter().map(|p| p.0).collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    let d = det3(a);
    if xs.len() < 3 || !d.is_finite() || d == 0.0 {
        return None;
    }
    let mut c = [0.0; 3];
    for (j, cj) in c.iter_mut().enumerate() {
        let mut m = a;
        for (row, tr) in m.iter_mut().zip(t) {
            row[j] = tr;
        }
        *cj = det3(m) / d;
    }
    Some(c)
}

#[cfg(test)]
mod tests {
    use super::{quadratic_fit, LLNL_ANFO_K1};

    #[test]
    fn the_parabola_fit_recovers_an_exact_parabola_and_refuses_two_points() {
        let pts: Vec<(f64, f64)> = [0.0, 0.05, 0.1, 0.15]
            .iter()
            .map(|&x| (x, 5900.0 - 3000.0 * x - 40000.0 * x * x))
            .collect();
        let c = quadratic_fit(&pts).unwrap();
        assert!((c[0] - 5900.0).abs() < 1e-6, "{c:?}");
        assert!((c[1] + 3000.0).abs() < 1e-4, "{c:?}");
        assert!((c[2] + 40000.0).abs() < 1e-3, "{c:?}");
        assert!(quadratic_fit(&[(0.0, 1.0), (1.0, 2.0), (1.0, 3.0)]).is_none());
    }

    #[test]
    fn the_llnl_parabola_passes_near_its_ideal_limit_and_falls_with_one_over_r() {
        // The fit's value at 1/R → 0 lies within the data's scatter of the
        // ideal-limit point (5890 m/s), and D falls across the data range.
        let c = quadratic_fit(&LLNL_ANFO_K1).unwrap();
        let d = |x: f64| c[0] + c[1] * x + c[2] * x * x;
        assert!((d(0.0) - 5890.0).abs() < 200.0, "{c:?}");
        assert!(
            d(0.0) > d(0.05) && d(0.05) > d(0.1) && d(0.1) > d(0.15),
            "{c:?}"
        );
    }
}
