//! The gas a remapped 1D detonation gives the particles of an MPM run
//! (seed 001 §5.2 starts its pure-MPM runs from the same remapped state as
//! the coupled ones): the `Mpm` pipeline's `remap` section
//! ([`MpmRemapConfig`]), its loaded form ([`GasRemap`], which tells the
//! particle builder which particles take a remapped cell's state), and the
//! cache of the remaps of a `charge` ([`cached_remap`]), which the
//! `FdmMpmBridge` pipeline's charge shares. Errors are `(field path,
//! message)` pairs, the path in the scenario (`pipeline.remap.file`).

use brisance_constitutive::MaterialModel;
use brisance_core::Eos;
use brisance_eos::EosModel;
use brisance_mpm::{MaterialId, ParticleInit};
use serde::{Deserialize, Serialize};

use crate::{Charge, Remapped};

/// A problem with one field: its path in the scenario and a sentence.
pub type Problem = (String, String);

/// Gas particles of the `Mpm` pipeline from a detonation remapped by
/// `brisance remap` (`pipeline: Mpm(remap: (file: ..., air: ...,
/// products: ...))`): the pure-MPM counterpart of the bridge's `remap`,
/// so both methods start from the same state (seed 001 §5.2 compares them).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MpmRemapConfig {
    /// The remap file (path relative to the working directory). Its grid
    /// has the domain's cell size and lies on the domain's cells; it may
    /// cover only part of the domain. Give it or `charge`.
    #[serde(default)]
    pub file: Option<String>,
    /// The charge whose 1D detonation the run makes and remaps onto the
    /// whole domain itself (cached as the bridge's `pipeline.charge`);
    /// cells beyond its remap radius hold the 1D run's ambient air. Give
    /// it or `file`.
    #[serde(default)]
    pub charge: Option<Charge>,
    /// Material (a `Null` fluid, the air's ideal gas) of particles in cells
    /// that are mostly air.
    pub air: String,
    /// Material (a `Null` fluid, the products' JWL) of particles in cells
    /// whose products mass fraction exceeds 1/2.
    pub products: String,
}

/// The error of an [`MpmRemapConfig`] with neither a file nor a charge.
fn mpm_remap_source_missing() -> Problem {
    (
        "pipeline.remap".into(),
        "give the remap's `file` or the `charge` the run remaps itself".into(),
    )
}

impl MpmRemapConfig {
    /// Checks an [`MpmRemapConfig`] at load: exactly one of `file` and
    /// `charge`, and a charge the 1D detonation can run.
    pub fn validate(&self) -> Result<(), Problem> {
        match (&self.file, &self.charge) {
            (None, None) => Err(mpm_remap_source_missing()),
            (Some(_), Some(_)) => Err((
                "pipeline.remap.charge".into(),
                "give the charge (the run remaps it) or a `file`, not both".into(),
            )),
            (None, Some(charge)) => charge
                .validate()
                .map_err(|e| ("pipeline.remap.charge".to_string(), e.to_string())),
            (Some(_), None) => Ok(()),
        }
    }
}

/// A loaded [`MpmRemapConfig`]: which particles it replaces and their
/// state.
pub struct GasRemap {
    remap: Remapped,
    air: (MaterialId, EosModel),
    products: (MaterialId, EosModel),
}

impl GasRemap {
    /// Loads the file and checks it against the domain `grid`; `names` and
    /// `models` are the MPM materials in their numbering. Errors name the
    /// field.
    pub fn new(
        cfg: &MpmRemapConfig,
        names: &[&str],
        models: &[MaterialModel],
        grid: &brisance_core::UniformGridGeometry,
        coordinates: brisance_core::Geometry,
    ) -> Result<Self, Problem> {
        let fluid = |name: &str, field: &str| -> Result<(MaterialId, EosModel), Problem> {
            let id = names.iter().position(|n| *n == name);
            match id.map(|i| (i, &models[i])) {
                Some((i, MaterialModel::Null(m))) => Ok((MaterialId(i as u16), m.eos.clone())),
                _ => Err((
                    format!("pipeline.remap.{field}"),
                    format!("`{name}` must be a material with a `Null` fluid model"),
                )),
            }
        };
        let air = fluid(&cfg.air, "air")?;
        let products = fluid(&cfg.products, "products")?;
        let (remap, file) = match (&cfg.file, &cfg.charge) {
            (Some(file), _) => (
                Remapped::load(std::path::Path::new(file))
                    .map_err(|e| ("pipeline.remap.file".to_string(), e.to_string()))?,
                file.as_str(),
            ),
            (None, Some(charge)) => (
                cached_remap(charge, *grid, coordinates)
                    .map_err(|e| ("pipeline.remap.charge".to_string(), e))?,
                "the charge's remap",
            ),
            (None, None) => return Err(mpm_remap_source_missing()),
        };
        let g = remap.geometry;
        for d in 0..3 {
            let h = grid.spacing[d];
            let offset = (g.origin[d] - grid.origin[d]) / h;
            let fits = (g.spacing[d] - h).abs() <= 1e-6 * h
                && (offset - offset.round()).abs() <= 1e-6
                && offset.round() >= 0.0
                && offset.round() as usize + g.cells[d] <= grid.cells[d];
            if !fits {
                return Err((
                    "pipeline.remap.file".into(),
                    format!(
                        "{}: its grid ({:?} cells of {:?} m from {:?}) does not lie on the domain's cells ({:?} of {:?} m from {:?})",
                        file, g.cells, g.spacing, g.origin, grid.cells, grid.spacing, grid.origin
                    ),
                ));
            }
        }
        Ok(Self {
            remap,
            air,
            products,
        })
    }

    /// Whether particles of `material` (the air or the products) take the
    /// remapped state where the remap covers them.
    pub fn replaces(&self, material: MaterialId) -> bool {
        material == self.air.0 || material == self.products.0
    }

    /// The particle at `x` of volume `volume` (m³) from the remapped cell
    /// containing it, `None` outside the remap's grid. Its density,
    /// velocity and specific internal energy are the cell's
    /// (ρ, ρu/ρ, E/ρ − ½|u|²), so the particles of a cell carry its mass,
    /// momentum and energy exactly; it is a products particle where the
    /// cell's products fraction ρY/ρ exceeds 1/2 (as the bridge's inflow),
    /// its stress −p I and temperature from that material's EOS.
    pub fn particle(&self, x: [f64; 3], volume: f64) -> Result<Option<ParticleInit>, String> {
        let g = &self.remap.geometry;
        let Some(c) = g.cell_containing(x) else {
            return Ok(None);
        };
        let n = g.linear_index(c);
        let f = |k: usize| self.remap.fields[k][n];
        let rho = f(0);
        let velocity = [f(1) / rho, f(2) / rho, f(3) / rho];
        let e = f(4) / rho - 0.5 * velocity.iter().map(|v| v * v).sum::<f64>();
        if !(rho > 0.0 && e.is_finite()) {
            return Err(format!(
                "remapped cell {c:?}: density {rho} kg/m³ and specific internal energy {e} J/kg are not a gas state"
            ));
        }
        let (material, eos) = if f(5) / rho > 0.5 {
            &self.products
        } else {
            &self.air
        };
        let p = eos.pressure(rho, e);
        Ok(Some(ParticleInit {
            position: x,
            velocity,
            mass: rho * volume,
            volume,
            stress: [-p, -p, -p, 0.0, 0.0, 0.0],
            temperature: eos.temperature(rho, e),
            specific_internal_energy: e,
            material: *material,
            ..Default::default()
        }))
    }
}

/// Where remaps of `pipeline.charge` are cached: `$BRISANCE_CACHE_DIR`,
/// else `$XDG_CACHE_HOME/brisance`, else `$HOME/.cache/brisance`; `None`
/// (no caching) when none is set.
pub fn remap_cache_dir() -> Option<std::path::PathBuf> {
    let var = |k: &str| std::env::var_os(k).filter(|v| !v.is_empty());
    var("BRISANCE_CACHE_DIR")
        .map(std::path::PathBuf::from)
        .or_else(|| var("XDG_CACHE_HOME").map(|d| std::path::PathBuf::from(d).join("brisance")))
        .or_else(|| var("HOME").map(|d| std::path::PathBuf::from(d).join(".cache/brisance")))
}

/// The remap of `charge` onto the FDM region `grid`: from the cache when
/// a file of the same inputs is there and reads back onto the same grid,
/// else made (the 1D detonation and the remap) and stored in the cache. A
/// cache that cannot be read or written only costs the remap's time.
pub fn cached_remap(
    charge: &Charge,
    grid: brisance_core::UniformGridGeometry,
    coordinates: brisance_core::Geometry,
) -> Result<Remapped, String> {
    let file = remap_cache_dir().map(|dir| {
        dir.join("remap")
            .join(format!("{:016x}.bin", charge.cache_key(&grid, coordinates)))
    });
    if let Some(r) = file
        .as_ref()
        .and_then(|f| Remapped::load(f).ok())
        .filter(|r| r.geometry.cells == grid.cells)
    {
        tracing::info!("remap of the charge read from the cache");
        return Ok(r);
    }
    let (_, r) = charge
        .detonate_and_remap(grid, coordinates)
        .map_err(|e| e.to_string())?;
    if let Some(f) = file {
        let stored = f
            .parent()
            .map_or(Ok(()), std::fs::create_dir_all)
            .map_err(|e| e.to_string())
            .and_then(|()| bincode::serialize(&r).map_err(|e| e.to_string()))
            .and_then(|bytes| brisance_io::write_atomic(&f, &bytes).map_err(|e| e.to_string()));
        if let Err(e) = stored {
            tracing::warn!(
                "the charge's remap could not be cached at {}: {e}",
                f.display()
            );
        }
    }
    Ok(r)
}
