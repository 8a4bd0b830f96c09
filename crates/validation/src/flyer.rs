//! A plate driven by a gas: the exact interface state of the Riemann
//! problem between an ideal gas at rest and a solid at rest, the gas on
//! the left at pressure p_g, the solid on the right at zero pressure.
//!
//! The gas expands through a centred rarefaction (isentropic, γ), the
//! solid is shocked along its linear Hugoniot U_s = c₀ + s u_p
//! (p = ρ₀ U_s u_p from a state at rest and zero pressure). The interface
//! holds one pressure p* and one velocity u*:
//!
//! - gas: u = 2c_g/(γ − 1) (1 − (p/p_g)^((γ−1)/(2γ))), decreasing in p;
//! - solid: u = (−c₀ + √(c₀² + 4 s p/ρ₀)) / (2s) (p/(ρ₀c₀) for s = 0),
//!   increasing in p;
//!
//! so the two curves cross once in (0, p_g), found by bisection to
//! round-off. Until the first reflected wave returns to the interface
//! (the release from the plate's free face, or the rarefaction's
//! reflection from the wall behind the gas) the interface pressure stays
//! p*, and a plate of thickness L carries the momentum p* t per unit area:
//! its mean velocity is p* t / (ρ₀ L).

/// The gas behind the plate: an ideal gas at rest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gas {
    /// Pressure, Pa.
    pub pressure: f64,
    /// Density, kg/m³.
    pub density: f64,
    /// Ratio of specific heats.
    pub gamma: f64,
}

/// The plate's material: a linear U_s–u_p Hugoniot from rest at zero
/// pressure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hugoniot {
    /// Reference density ρ₀, kg/m³.
    pub density: f64,
    /// Bulk sound speed c₀, m/s.
    pub c0: f64,
    /// Slope s of U_s = c₀ + s u_p.
    pub s: f64,
}

impl Hugoniot {
    /// The particle velocity behind a shock of pressure `p` from rest.
    pub fn particle_velocity(&self, p: f64) -> f64 {
        if self.s == 0.0 {
            return p / (self.density * self.c0);
        }
        (-self.c0 + (self.c0 * self.c0 + 4.0 * self.s * p / self.density).sqrt()) / (2.0 * self.s)
    }

    /// The shock speed U_s = c₀ + s u_p at particle velocity `u`.
    pub fn shock_speed(&self, u: f64) -> f64 {
        self.c0 + self.s * u
    }
}

impl Gas {
    /// The sound speed √(γ p/ρ).
    pub fn sound_speed(&self) -> f64 {
        (self.gamma * self.pressure / self.density).sqrt()
    }

    /// The gas's velocity after a rarefaction from rest down to `p`.
    pub fn rarefaction_velocity(&self, p: f64) -> f64 {
        let g = self.gamma;
        2.0 * self.sound_speed() / (g - 1.0)
            * (1.0 - (p / self.pressure).powf((g - 1.0) / (2.0 * g)))
    }
}

/// The interface state of the gas-driven plate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interface {
    /// Interface pressure p*, Pa.
    pub pressure: f64,
    /// Interface velocity u*, m/s.
    pub velocity: f64,
    /// The shock's speed into the plate, m/s.
    pub shock_speed: f64,
}

/// The exact interface state between `gas` and a plate of `solid`.
pub fn interface(gas: Gas, solid: Hugoniot) -> Interface {
    let (mut lo, mut hi) = (0.0, gas.pressure);
    // 200 halvings take the bracket below one ulp of p_g.
    for _ in 0..200 {
        let p = 0.5 * (lo + hi);
        if p <= lo || p >= hi {
            break;
        }
        if gas.rarefaction_velocity(p) > solid.particle_velocity(p) {
            lo = p;
        } else {
            hi = p;
        }
    }
    let pressure = 0.5 * (lo + hi);
    let velocity = solid.particle_velocity(pressure);
    Interface {
        pressure,
        velocity,
        shock_speed: solid.shock_speed(velocity),
    }
}

/// The plate's mean velocity at time `t` (before any reflected wave
/// reaches the interface): p* t / (ρ₀ L) for a plate of thickness `l`.
pub fn mean_velocity(state: Interface, solid: Hugoniot, l: f64, t: f64) -> f64 {
    state.pressure * t / (solid.density * l)
}

/// configs/flyer_icempm.ron's drive: an ideal gas (γ = 3) at the QM-100
/// booster's 1260 kg/m³ and 10 GPa.
pub const BOOSTER_GAS: Gas = Gas {
    pressure: 1.0e10,
    density: 1260.0,
    gamma: 3.0,
};

/// configs/flyer_icempm.ron's plate: the OFHC copper of the cylinder test
/// on its Mie–Grüneisen Hugoniot.
pub const COPPER: Hugoniot = Hugoniot {
    density: 8930.0,
    c0: 3619.7,
    s: 1.489,
};

/// The plate's thickness in configs/flyer_icempm.ron, m.
pub const PLATE: f64 = 0.01;

/// The tube's length in configs/flyer_icempm.ron, m.
pub const TUBE: f64 = 0.06;

/// One run of configs/flyer_icempm.ron.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlyerRun {
    /// The plate's mass-weighted mean velocity at the end, m/s.
    pub velocity: f64,
    /// The net mass step 2's rescale gave the fluids over the run
    /// (booked), as a fraction of their initial mass.
    pub rescaled: f64,
    /// The run's end, s.
    pub time: f64,
    /// Steps taken.
    pub steps: usize,
    /// Wall time of the stepping, s.
    pub wall_seconds: f64,
}

/// Runs configs/flyer_icempm.ron on `cells` cells along the tube (cubic
/// cells) with the MPM shape function `shape` (`Linear`, `Gimp`, ...).
pub fn run_flyer(cells: usize, shape: &str) -> Result<FlyerRun, String> {
    use brisance_compose::build::build_section;
    use brisance_compose::load_str;
    use brisance_core::Solver;

    let text = include_str!("../../../configs/flyer_icempm.ron");
    let h = TUBE / cells as f64;
    let sets = [
        format!("domain.cells=({cells},1,1)"),
        format!("domain.upper=({TUBE},{h},{h})"),
        format!("pipeline.mpm.shape_function={shape}"),
        "outputs.lineouts=[]".to_string(),
    ];
    let loaded = load_str("configs/flyer_icempm.ron", text, &sets).map_err(|e| e.to_string())?;
    let s = &loaded.scenario;
    let Some(section) = s.pipeline.section::<brisance_couple::IceMpmConfig>() else {
        return Err("configs/flyer_icempm.ron is not an IceMpm pipeline".into());
    };
    let mut solver = build_section(section, s).map_err(|e| loaded.locate(e).to_string())?;
    let t_end = s.time.end;
    let plate_mass: f64 = solver.mpm().particles().mass.iter().sum();
    let fluids = solver.conservation_totals().mass - plate_mass;
    let rescaled0 = solver.rescaled_totals().mass;
    let start = std::time::Instant::now();
    let mut steps = 0;
    while solver.time() < t_end * (1.0 - 1e-12) {
        let dt = solver.stable_dt().map_err(|e| e.to_string())?;
        solver
            .advance(dt.min(t_end - solver.time()))
            .map_err(|e| format!("flyer, {cells} cells, {shape}: {e}"))?;
        steps += 1;
    }
    let wall_seconds = start.elapsed().as_secs_f64();
    let ps = solver.mpm().particles();
    let (mut mv, mut m) = (0.0, 0.0);
    for (v, mass) in ps.velocity.iter().zip(&ps.mass) {
        mv += mass * v[0];
        m += mass;
    }
    Ok(FlyerRun {
        velocity: mv / m,
        rescaled: (solver.rescaled_totals().mass - rescaled0) / fluids,
        time: solver.time(),
        steps,
        wall_seconds,
    })
}

/// The drive of configs/shock_plate_mpm.ron, Pa: the flyer's interface
/// pressure p* to four digits, prescribed as a surface load.
pub const SHOCK_PLATE_DRIVE: f64 = 8.587e9;

/// The shocked region of configs/shock_plate_mpm.ron where
/// [`run_shock_plate`] measures the state: particles between these
/// distances from the plate's initial rear face at 2 µs, m (behind the
/// shock, which has run 7.96 mm, and clear of the loaded face).
pub const SHOCKED: [f64; 2] = [1.5e-3, 6.0e-3];

/// One run of configs/shock_plate_mpm.ron.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShockPlateRun {
    /// How far the rearmost particle has moved, m.
    pub rear_displacement: f64,
    /// Mean σ_xx of the particles in [`SHOCKED`], Pa.
    pub stress: f64,
    /// Their root-mean-square deviation from that mean, Pa.
    pub stress_rms: f64,
    /// Their mean velocity, m/s.
    pub velocity: f64,
    /// Its root-mean-square deviation, m/s.
    pub velocity_rms: f64,
    /// The run's end, s.
    pub time: f64,
    /// Steps taken.
    pub steps: usize,
}

/// Runs configs/shock_plate_mpm.ron on `cells` cells along the tube (cubic
/// cells, the load on the first particle layer) with the MPM shape
/// function `shape` (`Linear`, `Gimp`, `CpGimp`, ...).
pub fn run_shock_plate(cells: usize, shape: &str) -> Result<ShockPlateRun, String> {
    use brisance_compose::build::build_section;
    use brisance_compose::load_str;
    use brisance_core::Solver;

    let text = include_str!("../../../configs/shock_plate_mpm.ron");
    let h = TUBE / cells as f64;
    // The plate's rear face and its first particle layer (2 per cell).
    let rear = 0.02;
    let sets = [
        format!("domain.cells=({cells},1,1)"),
        format!("domain.upper=({TUBE},{h},{h})"),
        format!("pipeline.shape_function={shape}"),
        format!(
            "pipeline.surface_loads.0.region=Box(min: (0.0, -1.0, -1.0), max: ({}, 1.0, 1.0))",
            rear + 0.5 * h
        ),
    ];
    let loaded = load_str("configs/shock_plate_mpm.ron", text, &sets).map_err(|e| e.to_string())?;
    let s = &loaded.scenario;
    let Some(section) = s.pipeline.section::<brisance_couple::MpmConfig>() else {
        return Err("configs/shock_plate_mpm.ron is not an Mpm pipeline".into());
    };
    let mut solver = build_section(section, s).map_err(|e| loaded.locate(e).to_string())?;
    let t_end = s.time.end;
    let rearmost = |ps: &brisance_mpm::Particles| {
        ps.position
            .iter()
            .map(|x| x[0])
            .fold(f64::INFINITY, f64::min)
    };
    let rear0 = rearmost(solver.particles());
    let mut steps = 0;
    while solver.time() < t_end * (1.0 - 1e-12) {
        let dt = solver.stable_dt().map_err(|e| e.to_string())?;
        solver
            .advance(dt.min(t_end - solver.time()))
            .map_err(|e| format!("shock plate, {cells} cells, {shape}: {e}"))?;
        steps += 1;
    }
    let ps = solver.particles();
    let inside: Vec<usize> = (0..ps.len())
        .filter(|&p| {
            let d = ps.position[p][0] - rear;
            d > SHOCKED[0] && d < SHOCKED[1]
        })
        .collect();
    if inside.is_empty() {
        return Err("no particle in the shocked region".into());
    }
    let n = inside.len() as f64;
    let mean = |f: &dyn Fn(usize) -> f64| inside.iter().map(|&p| f(p)).sum::<f64>() / n;
    let stress = mean(&|p| ps.stress[p][0]);
    let velocity = mean(&|p| ps.velocity[p][0]);
    Ok(ShockPlateRun {
        rear_displacement: rearmost(ps) - rear0,
        stress,
        stress_rms: mean(&|p| (ps.stress[p][0] - stress).powi(2)).sqrt(),
        velocity,
        velocity_rms: mean(&|p| (ps.velocity[p][0] - velocity).powi(2)).sqrt(),
        time: solver.time(),
        steps,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const GAS: Gas = BOOSTER_GAS;

    #[test]
    fn both_sides_hold_the_interface_state() {
        let st = interface(GAS, COPPER);
        let (ug, us) = (
            GAS.rarefaction_velocity(st.pressure),
            COPPER.particle_velocity(st.pressure),
        );
        assert!((ug - us).abs() < 1e-9 * us, "{ug} vs {us}");
        // p = ρ₀ U_s u_p on the shock.
        let p = COPPER.density * st.shock_speed * st.velocity;
        assert!((p / st.pressure - 1.0).abs() < 1e-12);
        // The hand solution (independent bisection): 8.587 GPa, 241.6 m/s.
        assert!((st.pressure / 1e9 - 8.587).abs() < 5e-4, "{}", st.pressure);
        assert!((st.velocity - 241.6).abs() < 0.05, "{}", st.velocity);
    }

    #[test]
    fn a_weak_drive_gives_the_acoustic_split() {
        // Small p_g: p* = p_g Z_s/(Z_s + Z_g), u* = p*/Z_s.
        let gas = Gas {
            pressure: 1.0e3,
            density: 1.0,
            gamma: 1.4,
        };
        let solid = Hugoniot { s: 0.0, ..COPPER };
        let zs = solid.density * solid.c0;
        let zg = gas.density * gas.sound_speed();
        let st = interface(gas, solid);
        let exact = gas.pressure * zs / (zs + zg);
        assert!(
            (st.pressure / exact - 1.0).abs() < 1e-4,
            "{} vs {exact}",
            st.pressure
        );
        assert!((st.velocity - st.pressure / zs).abs() < 1e-12);
    }

    #[test]
    fn the_mean_velocity_is_the_impulse_over_the_mass() {
        let st = Interface {
            pressure: 8.0e9,
            velocity: 0.0,
            shock_speed: 0.0,
        };
        // 8 GPa × 2 µs / (8930 kg/m³ × 0.01 m) = 179.17... m/s.
        let v = mean_velocity(st, COPPER, 0.01, 2.0e-6);
        assert!((v - 16000.0 / 89.3).abs() < 1e-9);
    }
}
