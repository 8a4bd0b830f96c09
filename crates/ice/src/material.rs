//! Materials, initial states and exchange coefficients of an ICE run.

use serde::{Deserialize, Serialize};

use crate::equilibration::MAX_MATERIALS;

/// Why an ICE solver cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IceError {
    /// A parameter or initial state is out of range (the message names it).
    #[error("{0}")]
    Invalid(String),
}

/// One material's state in a cell at initialisation or on a fixed-state
/// boundary.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MaterialState {
    /// Volume fraction θ_r (> 0: an absent material is given a trace).
    pub volume_fraction: f64,
    /// The material's own (microscopic) density 1/v_r, kg/m³.
    pub density: f64,
    /// Velocity, m/s.
    pub velocity: [f64; 3],
}

/// The state of one cell: one pressure, one entry per material.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CellState {
    /// Pressure, Pa; with each material's density it sets the specific
    /// internal energy e_r(ρ_r, p).
    pub pressure: f64,
    /// Per material, in the solver's material order.
    pub materials: Vec<MaterialState>,
}

impl CellState {
    /// A cell filled by one material (θ = 1) of density `density` moving at
    /// `velocity`, at `pressure`.
    pub fn single(pressure: f64, density: f64, velocity: [f64; 3]) -> Self {
        Self {
            pressure,
            materials: vec![MaterialState {
                volume_fraction: 1.0,
                density,
                velocity,
            }],
        }
    }
}

/// Momentum and heat exchange coefficients K_rs and H_rs (seed 000 eqs 2,
/// 3, 29, 30), N×N row-major, symmetric, zero diagonal.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExchangeCoefficients {
    /// Number of materials N.
    pub materials: usize,
    /// K_rs, kg/(m³·s).
    pub momentum: Vec<f64>,
    /// H_rs, W/(m³·K).
    pub heat: Vec<f64>,
}

impl ExchangeCoefficients {
    /// The same K and H between every pair of `n` materials (the seed's
    /// FSI practice is K = 10¹⁵, heat exchange "at a lower rate").
    pub fn uniform(n: usize, k: f64, h: f64) -> Self {
        let fill = |c: f64| {
            (0..n * n)
                .map(|i| if i / n == i % n { 0.0 } else { c })
                .collect()
        };
        Self {
            materials: n,
            momentum: fill(k),
            heat: fill(h),
        }
    }

    /// Checks sizes, symmetry and signs; the message names the field.
    pub fn validate(&self, n: usize) -> Result<(), IceError> {
        if n == 0 || n > MAX_MATERIALS {
            return Err(IceError::Invalid(format!(
                "ice: {n} materials; between 1 and {MAX_MATERIALS} are supported"
            )));
        }
        for (name, m) in [("momentum", &self.momentum), ("heat", &self.heat)] {
            if self.materials != n || m.len() != n * n {
                return Err(IceError::Invalid(format!(
                    "ice: exchange field `{name}` has {} entries for {n} materials (need {})",
                    m.len(),
                    n * n
                )));
            }
            for r in 0..n {
                for s in 0..n {
                    let c = m[r * n + s];
                    if !(c >= 0.0 && c.is_finite()) {
                        return Err(IceError::Invalid(format!(
                            "ice: exchange field `{name}`[{r}][{s}] = {c}, expected a finite value ≥ 0"
                        )));
                    }
                    if c != m[s * n + r] {
                        return Err(IceError::Invalid(format!(
                            "ice: exchange field `{name}` is not symmetric at [{r}][{s}]"
                        )));
                    }
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_single_material_cell_fills_the_cell() {
        let c = CellState::single(2e5, 1.5, [1.0, -2.0, 0.5]);
        assert_eq!(c.pressure, 2e5);
        assert_eq!(
            c.materials,
            [MaterialState {
                volume_fraction: 1.0,
                density: 1.5,
                velocity: [1.0, -2.0, 0.5],
            }]
        );
    }

    #[test]
    fn uniform_coefficients_are_symmetric_with_zero_diagonal() {
        let x = ExchangeCoefficients::uniform(3, 1e15, 2.0);
        assert_eq!(x.momentum[0], 0.0);
        assert_eq!(x.momentum[1], 1e15);
        assert_eq!(x.heat[5], 2.0);
        assert!(x.validate(3).is_ok());
        let e = x.validate(2).unwrap_err();
        assert!(e.to_string().contains("momentum"), "{e}");
        let mut bad = x.clone();
        bad.heat[1] = 3.0;
        assert!(bad
            .validate(3)
            .unwrap_err()
            .to_string()
            .contains("symmetric"));
    }
}
