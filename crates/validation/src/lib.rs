//! Brisance validation: exact solutions the validation suite compares
//! against, written from the physics, the empirical Kingery–Bulmash blast
//! fits it compares free-air bursts with, Mott's fragmentation of shells
//! (E-PD-FRAG), and the case drivers (E-PLATE's plates under a spherical
//! charge through the bridge, E-BLAST2D's slab behind the 2D bridge and
//! E-COOKOFF's container among them) the
//! integration tests and `cargo xtask validate` share (the root package
//! re-exports the crate as `brisance::verification`).

pub mod blast;
pub mod blast2d;
pub mod bridge_blast;
pub mod bridge_shock;
pub mod cases;
pub mod conduction_contact;
pub mod cookoff;
pub mod cylinder;
pub mod flyer;
pub mod ice_mpm_cost;
pub mod kingery_bulmash;
pub mod mott;
pub mod open_faces;
pub mod pd_cylinder;
pub mod pd_fragmentation;
pub mod pd_tube;
pub mod plate;
pub mod rate_stick;
pub mod riemann;
pub mod ring;
pub mod rz_octant;
pub mod shock_tubes;
pub mod slab;
pub mod smooth;
pub mod sod_ice;
pub mod taylor;

/// The mean of `f` over the last tenth of `record` (its last ⌊n/10⌋
/// entries, at least the last one): the terminal figure of a wall
/// record. NaN for an empty record.
pub fn last_tenth_mean<T>(record: &[T], f: impl Fn(&T) -> f64) -> f64 {
    let n = record.len();
    let tail = &record[n - (n / 10).max(1).min(n)..];
    tail.iter().map(f).sum::<f64>() / tail.len() as f64
}

/// Whether `measured` lies within the relative `band` of `reference`:
/// |measured − reference| ≤ band |reference|. False where either is NaN
/// or the reference is 0 (nothing is within a band of nothing).
pub fn within_relative(measured: f64, reference: f64, band: f64) -> bool {
    ((measured - reference) / reference).abs() <= band
}

#[cfg(test)]
mod tests {
    use super::{last_tenth_mean, within_relative};

    #[test]
    fn the_band_is_relative_to_the_reference_and_closed() {
        assert!(within_relative(1.1, 1.0, 0.1 + 1e-15));
        assert!(!within_relative(1.1 + 1e-9, 1.0, 0.1));
        assert!(within_relative(-0.95, -1.0, 0.05 + 1e-15));
        assert!(!within_relative(-0.9, -1.0, 0.05));
        assert!(!within_relative(f64::NAN, 1.0, 0.5));
        assert!(!within_relative(0.0, 0.0, 0.5));
        assert!(!within_relative(1e-300, 0.0, 0.5));
    }

    #[test]
    fn the_terminal_figure_is_the_mean_of_the_last_tenth() {
        let record: Vec<f64> = (1..=20).map(f64::from).collect();
        // The last two of twenty: (19 + 20)/2.
        assert_eq!(last_tenth_mean(&record, |v| *v), 19.5);
        let pairs: Vec<(f64, f64)> = (0..30).map(|k| (0.0, f64::from(k))).collect();
        // The last three of thirty: (27 + 28 + 29)/3.
        assert_eq!(last_tenth_mean(&pairs, |p| p.1), 28.0);
        // Fewer than ten entries: the last one.
        assert_eq!(last_tenth_mean(&record[..4], |v| *v), 4.0);
        assert!(last_tenth_mean(&record[..0], |v| *v).is_nan());
    }
}
