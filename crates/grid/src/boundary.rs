//! Boundary conditions, one per domain face.

/// A face of the domain box.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Face {
    /// x = x_min
    XLow,
    /// x = x_max
    XHigh,
    /// y = y_min
    YLow,
    /// y = y_max
    YHigh,
    /// z = z_min
    ZLow,
    /// z = z_max
    ZHigh,
}

impl Face {
    /// All six faces in storage order.
    pub const ALL: [Face; 6] = [
        Face::XLow,
        Face::XHigh,
        Face::YLow,
        Face::YHigh,
        Face::ZLow,
        Face::ZHigh,
    ];

    /// The face on `side` (0 low, 1 high) of axis `axis`.
    pub fn of(axis: usize, side: usize) -> Face {
        Self::ALL[2 * axis + side]
    }

    /// Config name (`x_low`, ...).
    pub fn name(self) -> &'static str {
        ["x_low", "x_high", "y_low", "y_high", "z_low", "z_high"][self as usize]
    }
}

/// What the ghost cells behind a domain face hold.
#[derive(Debug, Clone, PartialEq)]
pub enum FaceBc {
    /// Zero gradient: every ghost layer copies the boundary cell, so what
    /// the boundary cell holds flows out, or in where it moves inwards.
    Outflow,
    /// Zero gradient for what leaves, a wall-like ghost for what would
    /// enter: the ghosts copy the boundary cell, except that where the
    /// vector component normal to the face points into the domain it is
    /// set to zero in the ghosts and the kinetic energy it carried is taken
    /// from the total-energy field, so the ghost keeps the cell's density,
    /// tangential motion and internal energy. This is the "diode" boundary
    /// of the FLASH code (Fryxell et al. 2000, ApJS 131, 273; FLASH User's
    /// Guide 4.x, Grid boundary conditions: zero gradient with the normal
    /// velocity in the guard cells set to zero where it points into the
    /// domain), for conservative Euler fields: `density` is the index of
    /// ρ, `energy` that of the total energy per unit volume E, and the
    /// normal momentum ρu_n is the field of kind
    /// [`crate::FieldKind::VectorComponent`] of the face's axis, so the
    /// ghost holds E − (ρu_n)²/(2ρ) and ρu_n = 0 there.
    OutflowOnly {
        /// Index of the density field ρ.
        density: usize,
        /// Index of the total-energy field E (per unit volume).
        energy: usize,
    },
    /// Mirror: ghost layer m copies interior layer m; the vector component
    /// normal to the face changes sign (a slip wall or symmetry plane).
    Reflective,
    /// Periodic: the ghosts copy the opposite side of the domain (must be set
    /// on both faces of an axis).
    Periodic,
    /// A fixed state: one value per stored field.
    Fixed(Vec<f64>),
}

/// Boundary conditions on the six faces.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundaryConditions {
    /// Indexed by [`Face`] as `usize`.
    pub faces: [FaceBc; 6],
}

impl BoundaryConditions {
    /// The same condition on every face.
    pub fn uniform(bc: FaceBc) -> Self {
        Self {
            faces: std::array::from_fn(|_| bc.clone()),
        }
    }

    /// The condition on `face`.
    pub fn get(&self, face: Face) -> &FaceBc {
        &self.faces[face as usize]
    }

    /// Checks the conditions against a field count: periodic faces come in
    /// pairs and fixed states have one value per field.
    pub fn validate(&self, n_fields: usize) -> Result<(), String> {
        for axis in 0..3 {
            let lo = matches!(self.faces[2 * axis], FaceBc::Periodic);
            let hi = matches!(self.faces[2 * axis + 1], FaceBc::Periodic);
            if lo != hi {
                return Err(format!(
                    "periodic boundary on {} needs periodic on {} too",
                    Face::of(axis, if lo { 0 } else { 1 }).name(),
                    Face::of(axis, if lo { 1 } else { 0 }).name()
                ));
            }
        }
        for face in Face::ALL {
            match self.get(face) {
                FaceBc::Fixed(v) if v.len() != n_fields => {
                    return Err(format!(
                        "fixed state on {} has {} values for {} fields",
                        face.name(),
                        v.len(),
                        n_fields
                    ));
                }
                FaceBc::OutflowOnly { density, energy }
                    if *density >= n_fields || *energy >= n_fields || density == energy =>
                {
                    return Err(format!(
                        "outflow-only face {}: density field {density} and energy field {energy} must be two of the {n_fields} fields",
                        face.name()
                    ));
                }
                _ => {}
            }
        }
        Ok(())
    }
}
