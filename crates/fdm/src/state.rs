//! Conservative and primitive states of the Euler equations (seed 001 eq 2).

use brisance_core::{Eos, EosError};

/// Index of ρ in the conservative vector.
pub const RHO: usize = 0;
/// Index of ρu_x; ρu_y and ρu_z follow.
pub const MOM: usize = 1;
/// Index of the total energy per unit volume E = ρe + ½ρ|u|².
pub const ENERGY: usize = 4;
/// Number of conservative flow variables.
pub const NVAR: usize = 5;
/// Index of the partial density ρY of detonation products, stored after
/// the flow variables when the gas law carries a species.
pub const SPECIES: usize = 5;
/// Field name of the stored ρY.
pub const SPECIES_NAME: &str = "products_density";

/// Field names of the stored conservative variables.
pub const CONSERVATIVE_NAMES: [&str; NVAR] = [
    "density",
    "momentum_x",
    "momentum_y",
    "momentum_z",
    "total_energy",
];

/// A primitive state: density, velocity, pressure.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PrimitiveState {
    /// Density, kg/m³.
    pub density: f64,
    /// Velocity, m/s.
    pub velocity: [f64; 3],
    /// Pressure, Pa.
    pub pressure: f64,
}

impl PrimitiveState {
    /// The conservative vector U (seed 001 eq 2) of this state.
    pub fn to_conservative<E: Eos + ?Sized>(&self, eos: &E) -> Result<[f64; NVAR], EosError> {
        let rho = self.density;
        let e = eos.specific_internal_energy(rho, self.pressure)?;
        let [u, v, w] = self.velocity;
        let kinetic = 0.5 * rho * (u * u + v * v + w * w);
        Ok([rho, rho * u, rho * v, rho * w, rho * e + kinetic])
    }

    /// The conservative vector and ρY of this state with products mass
    /// fraction `y` under the gas law `gas`.
    pub fn to_conservative_mixed<G: crate::gas::GasLaw>(
        &self,
        gas: &G,
        y: f64,
    ) -> Result<([f64; NVAR], f64), EosError> {
        let rho = self.density;
        let e = gas.gas_energy(rho, self.pressure, y)?;
        let [u, v, w] = self.velocity;
        let kinetic = 0.5 * rho * (u * u + v * v + w * w);
        Ok(([rho, rho * u, rho * v, rho * w, rho * e + kinetic], rho * y))
    }
}

/// Specific internal energy e = (E − ½ρ|u|²)/ρ from conservative values.
#[inline(always)]
pub fn specific_internal_energy(rho: f64, mx: f64, my: f64, mz: f64, energy: f64) -> f64 {
    (energy - 0.5 * (mx * mx + my * my + mz * mz) / rho) / rho
}

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_eos::IdealGas;

    #[test]
    fn conservative_state_of_a_moving_gas_is_hand_computed() {
        let gas = IdealGas::new(1.4, 1.0, 1.0);
        let s = PrimitiveState {
            density: 2.0,
            velocity: [1.0, -2.0, 0.5],
            pressure: 0.8,
        };
        let u = s.to_conservative(&gas).unwrap();
        // e = p/((γ−1)ρ) = 1; E = ρe + ½ρ|u|² = 2 + 5.25
        assert_eq!(u[RHO], 2.0);
        assert_eq!([u[1], u[2], u[3]], [2.0, -4.0, 1.0]);
        assert!((u[ENERGY] - 7.25).abs() < 1e-14);
        let e = specific_internal_energy(u[0], u[1], u[2], u[3], u[4]);
        assert!((e - 1.0).abs() < 1e-14);
    }
}
