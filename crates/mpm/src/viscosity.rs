//! Artificial bulk viscosity of the particles: the von Neumann–Richtmyer
//! quadratic term with Landshoff's linear term, as hydrocodes add it to the
//! pressure so that a shock is spread over a few cells instead of ringing.
//!
//! For a particle with rate of deformation D (tr D < 0 in compression),
//! density ρ, sound speed c and length l,
//!
//! q = ρ l (Q₁ l (tr D)² − Q₂ c tr D)   if tr D < 0,   q = 0 otherwise,
//!
//! the form and default coefficients of LS-DYNA (*CONTROL_BULK_VISCOSITY,
//! Q₁ = 1.5 quadratic, Q₂ = 0.06 linear; Hallquist, LS-DYNA Theory Manual,
//! "Bulk viscosity"). Uintah's MPM `artificial_viscosity` option uses the
//! same two terms, q = ρ (A₁ |c tr D l| + A₂ (tr D)² l²), with A₁ = 0.2 and
//! A₂ = 2.0 (`artificial_viscosity_coeff1/2`); both sets are valid inputs.
//!
//! The viscous pressure acts like a pressure: the stress the grid sees is
//! σ − q I (see [`crate::step::update_particle_stress`]), its work −q tr D
//! enters the particle's internal energy through the stress power of seed
//! 001 eq 13, and the stable time step uses the signal speed of LS-DYNA's
//! element time step with bulk viscosity, Q + √(Q² + c²) with
//! Q = Q₂ c + Q₁ l |tr D| in compression (Q = 0 otherwise).
//!
//! `l` is the cell size: the geometric mean of the grid spacing over the
//! active axes (Δx on a uniform 1D, 2D or 3D grid), because the velocity
//! gradient a particle sees is formed on the grid and a shock is smeared
//! over cells, not particles. `c` is the material's
//! [`brisance_core::Material::wave_speed`] (the EOS sound speed of a fluid,
//! the longitudinal speed of a solid).

use brisance_core::UniformGridGeometry;
use serde::{Deserialize, Serialize};

/// The coefficients of the artificial bulk viscosity.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BulkViscosity {
    /// Quadratic (von Neumann–Richtmyer) coefficient Q₁, ≥ 0.
    #[serde(default = "default_quadratic")]
    pub quadratic: f64,
    /// Linear (Landshoff) coefficient Q₂, ≥ 0.
    #[serde(default = "default_linear")]
    pub linear: f64,
}

fn default_quadratic() -> f64 {
    BulkViscosity::LS_DYNA.quadratic
}

fn default_linear() -> f64 {
    BulkViscosity::LS_DYNA.linear
}

impl Default for BulkViscosity {
    fn default() -> Self {
        Self::LS_DYNA
    }
}

/// The per-particle state of the bulk viscosity: the q in the particle's
/// stress and the tr D it was formed from (for the time step).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct BulkViscosityState {
    /// Viscous pressure q, Pa (≥ 0); the stored stress is σ_material − q I.
    pub q: f64,
    /// tr D of the last stress update, 1/s.
    pub trace_d: f64,
}

impl BulkViscosity {
    /// LS-DYNA's defaults: Q₁ = 1.5, Q₂ = 0.06.
    pub const LS_DYNA: Self = Self {
        quadratic: 1.5,
        linear: 0.06,
    };

    /// Uintah MPM's defaults: A₂ = 2.0 (quadratic), A₁ = 0.2 (linear).
    pub const UINTAH: Self = Self {
        quadratic: 2.0,
        linear: 0.2,
    };

    /// Checks the coefficients: finite and ≥ 0. Returns the name of the bad
    /// coefficient and its value.
    pub fn validate(&self) -> Result<(), (&'static str, f64)> {
        for (name, v) in [("quadratic", self.quadratic), ("linear", self.linear)] {
            if !(v >= 0.0) || !v.is_finite() {
                return Err((name, v));
            }
        }
        Ok(())
    }

    /// q = ρ l (Q₁ l (tr D)² − Q₂ c tr D) for tr D < 0, else 0, Pa.
    #[inline]
    pub fn pressure(&self, trace_d: f64, density: f64, sound_speed: f64, length: f64) -> f64 {
        if trace_d < 0.0 {
            density
                * length
                * (self.quadratic * length * trace_d * trace_d
                    - self.linear * sound_speed * trace_d)
        } else {
            0.0
        }
    }

    /// The signal speed of the time step, Q + √(Q² + c²) with
    /// Q = Q₂ c + Q₁ l |tr D| for tr D < 0; c itself otherwise, m/s.
    #[inline]
    pub fn signal_speed(&self, trace_d: f64, sound_speed: f64, length: f64) -> f64 {
        if trace_d < 0.0 {
            let q = self.linear * sound_speed - self.quadratic * length * trace_d;
            q + (q * q + sound_speed * sound_speed).sqrt()
        } else {
            sound_speed
        }
    }
}

/// The viscosity's length l: the geometric mean of the spacing over the
/// active axes (more than one cell), m; the mean over all three axes when
/// none is active.
pub fn viscosity_length(grid: &UniformGridGeometry) -> f64 {
    let active: Vec<f64> = (0..3)
        .filter(|&d| grid.cells[d] > 1)
        .map(|d| grid.spacing[d])
        .collect();
    let lengths: &[f64] = if active.is_empty() {
        &grid.spacing
    } else {
        &active
    };
    lengths
        .iter()
        .product::<f64>()
        .powf(1.0 / lengths.len() as f64)
}

/// What the stress update needs: the coefficients and the length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViscosityParams {
    /// The coefficients of every particle (`None`: none but the fluids').
    pub model: Option<BulkViscosity>,
    /// The coefficients of the particles of a `Null` fluid, in place of
    /// `model` (`None`: `model`'s).
    pub fluid: Option<BulkViscosity>,
    /// The length l, m.
    pub length: f64,
}

impl ViscosityParams {
    /// The same coefficients for every particle.
    pub fn new(model: BulkViscosity, length: f64) -> Self {
        Self {
            model: Some(model),
            fluid: None,
            length,
        }
    }

    /// The coefficients of a particle of a fluid (`fluid`) or of a solid,
    /// with the length l; `None` where that particle takes no viscosity.
    #[inline]
    pub fn coefficients(&self, fluid: bool) -> Option<(BulkViscosity, f64)> {
        let model = if fluid {
            self.fluid.or(self.model)
        } else {
            self.model
        };
        model.map(|m| (m, self.length))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pressure_is_the_ls_dyna_form_in_compression_and_zero_in_expansion() {
        let v = BulkViscosity::LS_DYNA;
        // ρ = 2, l = 0.5, c = 10, tr D = −4:
        // q = 2·0.5·(1.5·0.5·16 − 0.06·10·(−4)) = 1·(12 + 2.4) = 14.4.
        let q = v.pressure(-4.0, 2.0, 10.0, 0.5);
        assert!((q - 14.4).abs() < 1e-13, "{q}");
        assert_eq!(v.pressure(0.0, 2.0, 10.0, 0.5), 0.0);
        assert_eq!(v.pressure(3.0, 2.0, 10.0, 0.5), 0.0);
        // Only the linear term: q = ρ l Q₂ c |tr D| = 1·0.5·0.2·3·2 = 0.6.
        let linear = BulkViscosity {
            quadratic: 0.0,
            linear: 0.2,
        };
        assert!((linear.pressure(-2.0, 1.0, 3.0, 0.5) - 0.6).abs() < 1e-15);
    }

    #[test]
    fn uintah_coefficients_give_uintah_q() {
        // Uintah: q = ρ (A₁ |c D l| + A₂ D² l²) with A₁ = 0.2, A₂ = 2.
        let (d, rho, c, l): (f64, f64, f64, f64) = (-3.0, 1.5, 7.0, 0.25);
        let uintah = rho * (0.2 * (c * d * l).abs() + 2.0 * d * d * l * l);
        let q = BulkViscosity::UINTAH.pressure(d, rho, c, l);
        assert!((q - uintah).abs() < 1e-14 * uintah, "{q} {uintah}");
    }

    #[test]
    fn signal_speed_is_q_plus_root_of_q2_plus_c2() {
        let v = BulkViscosity::LS_DYNA;
        // c = 10, l = 0.5, tr D = −4: Q = 0.6 + 1.5·0.5·4 = 3.6,
        // Q + √(Q² + c²) = 3.6 + √(12.96 + 100) = 3.6 + √112.96.
        let s = v.signal_speed(-4.0, 10.0, 0.5);
        assert!((s - (3.6 + 112.96_f64.sqrt())).abs() < 1e-13, "{s}");
        assert_eq!(v.signal_speed(1.0, 10.0, 0.5), 10.0);
        assert_eq!(v.signal_speed(0.0, 10.0, 0.5), 10.0);
        assert!(v.signal_speed(-1e-3, 10.0, 0.5) > 10.0);
    }

    #[test]
    fn length_is_the_geometric_mean_of_the_active_spacings() {
        let grid = |spacing, cells| UniformGridGeometry {
            origin: [0.0; 3],
            spacing,
            cells,
        };
        assert_eq!(viscosity_length(&grid([0.01, 0.5, 0.5], [100, 1, 1])), 0.01);
        let l = viscosity_length(&grid([0.02, 0.08, 7.0], [10, 10, 1]));
        assert!((l - 0.04).abs() < 1e-16, "{l}");
        let l = viscosity_length(&grid([1.0, 2.0, 4.0], [1, 1, 1]));
        assert!((l - 2.0).abs() < 1e-15, "{l}");
    }

    // ------------------------------------------- in the particle stress update

    use crate::step::{update_particle_stress, ParticleState};
    use crate::MaterialId;
    use brisance_constitutive::PressureModel;
    use brisance_constitutive::{Hypoelastic, MaterialModel, NullMaterial, ObjectiveRate};
    use brisance_core::{Mat3, Material};

    /// One particle's mutable state, as plain values.
    #[derive(Debug, Clone, PartialEq)]
    struct One {
        stress: [f64; 6],
        f: [f64; 9],
        volume: f64,
        temperature: f64,
        e: f64,
        failed: bool,
        history: Vec<f64>,
        bulk: BulkViscosityState,
    }

    impl One {
        fn new(stress: [f64; 6], volume: f64, e: f64) -> Self {
            Self {
                stress,
                f: crate::particles::IDENTITY,
                volume,
                temperature: 300.0,
                e,
                failed: false,
                history: vec![0.0; 8],
                bulk: BulkViscosityState::default(),
            }
        }

        fn update(
            &mut self,
            m: &MaterialModel,
            l: &Mat3,
            mass: f64,
            v0: f64,
            dt: f64,
            visc: Option<ViscosityParams>,
        ) {
            let state = ParticleState {
                stress: &mut self.stress,
                deformation_gradient: &mut self.f,
                volume: &mut self.volume,
                temperature: &mut self.temperature,
                specific_internal_energy: &mut self.e,
                failed: &mut self.failed,
                history: &mut self.history,
                bulk_viscosity: &mut self.bulk,
            };
            update_particle_stress(m, MaterialId(0), state, l, mass, v0, dt, visc).unwrap();
        }
    }

    /// The γ = 1.4 ideal gas: p = 0.4 ρ e, c = √(1.4 p/ρ).
    fn gas() -> MaterialModel {
        MaterialModel::Null(NullMaterial::air())
    }

    #[test]
    fn the_stress_update_subtracts_the_hand_computed_q_from_the_gas_pressure() {
        // A unit gas particle (m = 1 kg, V = 1 m³, e = 2.5 J/kg, p = 1 Pa)
        // compressed along x at tr D = −0.5 /s for Δt = 0.1 s:
        // F = 1 − 0.05, V = 0.95, ρ = 1/0.95.
        let m = gas();
        let l = Mat3::new(-0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let visc = ViscosityParams::new(BulkViscosity::LS_DYNA, 0.2);
        let mut on = One::new([-1.0, -1.0, -1.0, 0.0, 0.0, 0.0], 1.0, 2.5);
        let mut off = on.clone();
        on.update(&m, &l, 1.0, 1.0, 0.1, Some(visc));
        off.update(&m, &l, 1.0, 1.0, 0.1, None);
        let rho: f64 = 1.0 / 0.95;
        // The EOS pressure at (ρ, eⁿ): p = 0.4 ρ 2.5 = ρ; c = √(1.4 p/ρ) = √1.4.
        let c = 1.4_f64.sqrt();
        assert!((m.wave_speed(rho, 2.5) - c).abs() < 1e-15);
        // q = ρ l (1.5 l 0.25 + 0.06 c 0.5) = ρ 0.2 (0.075 + 0.03 √1.4).
        let q = rho * 0.2 * (0.075 + 0.03 * c);
        assert!((on.bulk.q - q).abs() < 1e-15, "{} {q}", on.bulk.q);
        assert_eq!(on.bulk.trace_d, -0.5);
        assert_eq!(off.bulk.q, 0.0);
        for k in 0..3 {
            assert!((off.stress[k] + rho).abs() < 1e-15, "{}", off.stress[k]);
            assert!((on.stress[k] - (off.stress[k] - q)).abs() < 1e-15);
        }
        assert_eq!(&on.stress[3..], &[0.0; 3]);
        assert_eq!(on.volume, off.volume);
        // The reported material pressure is the EOS one: −tr σ/3 − q.
        let p_material = -(on.stress[0] + on.stress[1] + on.stress[2]) / 3.0 - on.bulk.q;
        assert!((p_material - rho).abs() < 1e-15);
    }

    #[test]
    fn fluids_take_their_own_coefficients_and_solids_the_common_ones() {
        // The gas of the test above and a hypoelastic solid under the same
        // compression, with LS-DYNA's coefficients for all and Q₂ = 1.0 for
        // the fluids: the gas's q is the hand value with Q₂ = 1.0, the
        // solid's LS-DYNA's; fluids alone (no common coefficients): the
        // solid gets none; no fluid coefficients: the gas takes LS-DYNA's.
        let strong = BulkViscosity {
            quadratic: 1.5,
            linear: 1.0,
        };
        let split = ViscosityParams {
            model: Some(BulkViscosity::LS_DYNA),
            fluid: Some(strong),
            length: 0.2,
        };
        assert_eq!(split.coefficients(true), Some((strong, 0.2)));
        assert_eq!(
            split.coefficients(false),
            Some((BulkViscosity::LS_DYNA, 0.2))
        );
        let fluid_only = ViscosityParams {
            model: None,
            ..split
        };
        assert_eq!(fluid_only.coefficients(false), None);
        let common = ViscosityParams::new(BulkViscosity::LS_DYNA, 0.2);
        assert_eq!(
            common.coefficients(true),
            Some((BulkViscosity::LS_DYNA, 0.2))
        );

        let l = Mat3::new(-0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let rho: f64 = 1.0 / 0.95;
        let c = 1.4_f64.sqrt();
        let mut g = One::new([-1.0, -1.0, -1.0, 0.0, 0.0, 0.0], 1.0, 2.5);
        g.update(&gas(), &l, 1.0, 1.0, 0.1, Some(split));
        // q = ρ l (1.5 l 0.25 + 1.0 c 0.5) = ρ 0.2 (0.075 + 0.5 √1.4).
        let q = rho * 0.2 * (0.075 + 0.5 * c);
        assert!((g.bulk.q - q).abs() < 1e-15, "{} {q}", g.bulk.q);

        let solid = MaterialModel::Hypoelastic(Hypoelastic {
            shear_modulus: 3.0e9,
            pressure: PressureModel::Linear {
                bulk_modulus: 8.0e9,
            },
            rate: ObjectiveRate::Jaumann,
        });
        let (rho0, v0) = (2000.0, 1e-6);
        let l = Mat3::new(-300.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let mut a = One::new([0.0; 6], v0, 0.0);
        let mut b = a.clone();
        let mut n = a.clone();
        a.update(&solid, &l, rho0 * v0, v0, 1e-6, Some(split));
        b.update(&solid, &l, rho0 * v0, v0, 1e-6, Some(common));
        n.update(&solid, &l, rho0 * v0, v0, 1e-6, Some(fluid_only));
        assert!(a.bulk.q > 0.0);
        assert_eq!(a, b);
        assert_eq!(n.bulk.q, 0.0);
    }

    #[test]
    fn the_viscous_work_is_the_energy_the_particle_gains() {
        // A hypoelastic particle (its stress does not depend on e), three
        // compressive steps with and without q: the energy difference is the
        // trapezoidal work of q, Σ Δt (qⁿ + qⁿ⁺¹)/2 |tr D| / ρ^{n+½}, and the
        // stress difference is −q I.
        let m = MaterialModel::Hypoelastic(Hypoelastic {
            shear_modulus: 3.0e9,
            pressure: PressureModel::Linear {
                bulk_modulus: 8.0e9,
            },
            rate: ObjectiveRate::Jaumann,
        });
        let rho0 = 2000.0;
        let v0 = 1e-6;
        let mass = rho0 * v0;
        let visc = ViscosityParams::new(BulkViscosity::UINTAH, 1e-3);
        let l = Mat3::new(-300.0, 20.0, 0.0, -20.0, -100.0, 0.0, 0.0, 0.0, 50.0);
        let dt = 1e-6;
        let mut on = One::new([0.0; 6], v0, 0.0);
        let mut off = on.clone();
        let mut work = 0.0;
        for _ in 0..3 {
            let (q_old, v_old) = (on.bulk.q, on.volume);
            on.update(&m, &l, mass, v0, dt, Some(visc));
            off.update(&m, &l, mass, v0, dt, None);
            assert_eq!(on.volume, off.volume);
            let rho_mid = 2.0 * mass / (v_old + on.volume);
            let c = m.wave_speed(mass / on.volume, 0.0);
            let q = visc
                .model
                .unwrap()
                .pressure(-350.0, mass / on.volume, c, 1e-3);
            assert!((on.bulk.q - q).abs() < 1e-12 * q);
            work += dt * 0.5 * (q_old + on.bulk.q) * 350.0 / rho_mid;
            for k in 0..3 {
                let diff = on.stress[k] - off.stress[k] + on.bulk.q;
                assert!(diff.abs() < 1e-9 * q, "component {k}: {diff}");
            }
        }
        assert!(work > 0.0);
        let gained = on.e - off.e;
        assert!(
            (gained - work).abs() < 1e-12 * work,
            "gained {gained} J/kg, viscous work {work} J/kg"
        );
    }

    /// A metal heated by the work of q through a specific heat that follows
    /// the temperature (the 4340 steel's Curie form): its heat H(T) rises by
    /// the viscous work, step by step, as its energy does; without q its
    /// temperature stays (the steps are elastic).
    #[test]
    fn the_viscous_work_heats_a_metal_through_its_specific_heat_curve() {
        use brisance_constitutive::{ElasticPlastic, SpecificHeat};
        let curie = SpecificHeat::steel_4340();
        let m = MaterialModel::ElasticPlastic(ElasticPlastic {
            specific_heat: curie.clone(),
            ..ElasticPlastic::steel_4340_seed000()
        });
        let v0 = 1e-6;
        let mass = 7830.0 * v0;
        let visc = ViscosityParams::new(BulkViscosity::UINTAH, 1e-3);
        let l = Mat3::new(-300.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let dt = 1e-6;
        let mut on = One::new([0.0; 6], v0, 0.0);
        on.history = vec![0.0; m.history_len()];
        m.init_history(&mut on.history);
        let mut off = on.clone();
        let mut work = 0.0;
        for _ in 0..3 {
            let (q_old, v_old) = (on.bulk.q, on.volume);
            on.update(&m, &l, mass, v0, dt, Some(visc));
            off.update(&m, &l, mass, v0, dt, None);
            let rho_mid = 2.0 * mass / (v_old + on.volume);
            work += dt * 0.5 * (q_old + on.bulk.q) * 300.0 / rho_mid;
        }
        assert!(work > 0.0);
        assert_eq!(off.temperature, 300.0);
        let held = curie.heat(on.temperature) - curie.heat(300.0);
        assert!((held - work).abs() < 1e-9 * work, "{held} vs {work}");
        // Not the rise of the constant c_v the library's steel carries.
        let constant = on.temperature - 300.0 - work / 477.0;
        assert!(constant.abs() > 1e-3 * (work / 477.0), "{constant}");
    }

    #[test]
    fn without_compression_there_is_no_q_and_the_update_is_unchanged() {
        let m = gas();
        let l = Mat3::new(0.3, 0.0, 0.0, 0.0, 0.1, 0.0, 0.0, 0.0, 0.0);
        let visc = ViscosityParams::new(BulkViscosity::LS_DYNA, 0.2);
        let mut on = One::new([-1.0, -1.0, -1.0, 0.0, 0.0, 0.0], 1.0, 2.5);
        let mut off = on.clone();
        on.update(&m, &l, 1.0, 1.0, 0.1, Some(visc));
        off.update(&m, &l, 1.0, 1.0, 0.1, None);
        assert_eq!(on.bulk.q, 0.0);
        assert_eq!(on.stress, off.stress);
        assert_eq!(on.e.to_bits(), off.e.to_bits());
    }

    #[test]
    fn negative_or_non_finite_coefficients_are_rejected_by_name() {
        assert!(BulkViscosity::LS_DYNA.validate().is_ok());
        let bad = BulkViscosity {
            quadratic: -1.0,
            linear: 0.06,
        };
        assert_eq!(bad.validate(), Err(("quadratic", -1.0)));
        let bad = BulkViscosity {
            quadratic: 1.5,
            linear: f64::NAN,
        };
        assert_eq!(bad.validate().unwrap_err().0, "linear");
    }
}
