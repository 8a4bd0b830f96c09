//! Tools that work on any products EOS through the [`brisance_core::Eos`]
//! trait: the CJ state by Rayleigh-line tangency ([`crate::tools::cj`]),
//! isentropes and the principal isentrope ([`crate::tools::isentrope`]), the
//! Gurney velocity estimate ([`crate::tools::gurney`]) and the volume-burn
//! reference pressure of seed 004 eqs 20–21 ([`crate::tools::volume_burn`]).
//! They iterate and may allocate; the EOS evaluations they call do not.

pub mod cj;
pub mod gurney;
pub mod isentrope;
pub mod volume_burn;

pub use cj::{
    chapman_jouguet, cj_on_jwl_cterm_isentrope, jwl_cterm_unreacted_state, CjState, UnreactedState,
};
pub use gurney::{cylinder_wall_velocity, gurney_estimate, GurneyEstimate};
pub use isentrope::{principal_isentrope, IsentropePoint};
pub use volume_burn::{volume_burn_reference, VolumeBurnReference};

use crate::{Jwl, JwlCTerm};
use brisance_core::EosError;

/// Why a tool could not produce its result.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ToolError {
    /// The EOS refused a state.
    #[error(transparent)]
    Eos(#[from] EosError),
    /// An input was out of range.
    #[error("{tool}: invalid input: {detail}")]
    InvalidInput {
        /// Which tool.
        tool: &'static str,
        /// What was wrong, with values.
        detail: String,
    },
    /// The problem has no solution the tool could find.
    #[error("{tool}: no solution: {detail}")]
    NoSolution {
        /// Which tool.
        tool: &'static str,
        /// What failed, with values.
        detail: String,
    },
}

/// One row of the V-CJ validation table: a computed CJ state beside the
/// published values.
#[derive(Debug, Clone, PartialEq)]
pub struct CjCase {
    /// Material (file-name style: `tnt`, `anfo_k1`, `qm100`).
    pub material: &'static str,
    /// Products EOS model name.
    pub eos: &'static str,
    /// How the CJ state was computed.
    pub method: &'static str,
    /// The computed CJ state.
    pub computed: Result<CjState, ToolError>,
    /// Published detonation velocity, m/s, if any.
    pub reference_detonation_velocity: Option<f64>,
    /// Published CJ pressure, Pa, if any.
    pub reference_pressure: Option<f64>,
    /// Where the published values come from.
    pub reference_source: &'static str,
}

/// The V-CJ cases: TNT (JWL, seed 001 §4.1), ANFO-K1 and QM-100 (JWL
/// C-term, seed 000 §5.1–5.2).
pub fn v_cj_report() -> Vec<CjCase> {
    let tnt = Jwl::tnt();
    let tnt_unreacted = UnreactedState {
        density: tnt.rho0,
        specific_internal_energy: tnt.specific_detonation_energy(),
        pressure: 0.0,
    };
    vec![
        CjCase {
            material: "tnt",
            eos: "jwl",
            method: "Rayleigh line tangent to the products Hugoniot from (ρ₀ = 1630 kg/m³, e₀ = E₀/ρ₀, p₀ = 0)",
            computed: chapman_jouguet(&tnt, &tnt_unreacted),
            reference_detonation_velocity: Some(6930.0),
            reference_pressure: Some(21.0e9),
            reference_source: "D: seed 001 §4.1 (6930 m/s); P_CJ: Dobratz & Crawford, LLNL Explosives Handbook, UCRL-52997 (1985), TNT JWL set (0.210 Mbar)",
        },
        CjCase {
            material: "anfo_k1",
            eos: "jwl_cterm",
            method: "Rayleigh line from (ρ₀ = 1160 kg/m³, p₀ = 0) tangent to the reference isentrope A e^{−R₁V} + B e^{−R₂V} + C V^{−(1+ω)}",
            computed: cj_on_jwl_cterm_isentrope(&JwlCTerm::anfo_k1()),
            reference_detonation_velocity: Some(ANFO_K1_LARGE_RADIUS_D),
            reference_pressure: None,
            reference_source: ANFO_K1_REFERENCE,
        },
        CjCase {
            material: "qm100",
            eos: "jwl_cterm",
            method: "Rayleigh line from (ρ₀ = 1260 kg/m³, p₀ = 0) tangent to the reference isentrope A e^{−R₁V} + B e^{−R₂V} + C V^{−(1+ω)}",
            computed: cj_on_jwl_cterm_isentrope(&JwlCTerm::qm100()),
            reference_detonation_velocity: None,
            reference_pressure: None,
            reference_source: QM100_REFERENCE,
        },
    ]
}

/// Detonation velocity of ANFO-K1 at the largest radius of the LLNL
/// size-effect data (1/R ≈ 4 × 10⁻⁴ mm⁻¹, the near-ideal limit), m/s: the
/// experimental points of Souers et al. (2000) shown in seed 000 Fig. 3,
/// read from the digitised set published with the blastFoam rate-stick
/// validation (`experimental_LNLL.csv`). The JWL++ products set was fitted
/// to this ideal limit, so the CJ velocity of the C-term isentrope should
/// match it.
const ANFO_K1_LARGE_RADIUS_D: f64 = 5890.0;

const ANFO_K1_REFERENCE: &str = "D: largest-radius point (1/R ≈ 4e-4 1/mm) of the LLNL ANFO-K1 size-effect data of Souers et al., JWL++: a simple reactive flow code package for detonation, Propellants Explos. Pyrotech. 25 (2000) 54–58, shown in seed 000 Fig. 3 (digitised values of the blastFoam rate-stick validation set); no published CJ pressure for this set was found";
const QM100_REFERENCE: &str = "no published CJ state or detonation velocity for the seed 000 §5.2 QM-100 JWL++ set was found; seed 000 §5.2 compares cylinder-wall velocities (LLNL shot K260-581), not CJ values";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn v_cj_tnt_within_three_percent() {
        let report = v_cj_report();
        let tnt = report.iter().find(|c| c.material == "tnt").unwrap();
        let cj = tnt.computed.as_ref().unwrap();
        let d_err = (cj.detonation_velocity - 6930.0).abs() / 6930.0;
        let p_err = (cj.pressure - 21.0e9).abs() / 21.0e9;
        assert!(
            d_err < 0.03,
            "D = {} m/s, {:.2} % from 6930",
            cj.detonation_velocity,
            100.0 * d_err
        );
        assert!(
            p_err < 0.03,
            "P_CJ = {} Pa, {:.2} % from 21 GPa",
            cj.pressure,
            100.0 * p_err
        );
    }

    #[test]
    fn v_cj_anfo_k1_matches_the_large_radius_detonation_velocity_within_three_percent() {
        let report = v_cj_report();
        let anfo = report.iter().find(|c| c.material == "anfo_k1").unwrap();
        let d = anfo.computed.as_ref().unwrap().detonation_velocity;
        let d_ref = anfo.reference_detonation_velocity.unwrap();
        let err = (d - d_ref).abs() / d_ref;
        assert!(err < 0.03, "D = {d} m/s, {:.2} % from {d_ref}", 100.0 * err);
    }

    #[test]
    fn v_cj_cterm_cases_have_a_cj_state() {
        for case in v_cj_report().iter().filter(|c| c.eos == "jwl_cterm") {
            let cj = case.computed.as_ref().unwrap();
            // CJ is sonic and compressive.
            let d = cj.detonation_velocity;
            assert!(
                (cj.particle_velocity + cj.sound_speed - d).abs() < 1e-5 * d,
                "{case:?}"
            );
            assert!(cj.relative_volume < 1.0 && cj.pressure > 0.0, "{case:?}");
        }
    }
}
