//! V-TAYLOR: the Taylor impact of an OFHC copper rod on a rigid wall
//! (`configs/taylor3d.ron`), measured the same way by the integration test
//! and by `cargo xtask validate`.
//!
//! # The test
//!
//! Johnson & Cook, *A constitutive model and data for metals subjected to
//! large strains, high strain rates and high temperatures*, Proc. 7th Int.
//! Symp. on Ballistics, The Hague (1983) 541–547, give the Johnson–Cook
//! constants of OFHC copper (A = 90 MPa, B = 292 MPa, n = 0.31, C = 0.025,
//! m = 1.09, T_melt = 1356 K, c_p = 383 J/(kg·K), ε̇₀ = 1 s⁻¹) and compare
//! them with cylinder-impact tests of rods L₀ = 25.4 mm long and
//! D₀ = 7.62 mm across. The 190 m/s test ended at L_f/L₀ = 0.638 and a
//! foot ("mushroom") diameter D_f/D₀ = 1.78, i.e. L_f = 16.21 mm and
//! D_f = 13.56 mm. These ratios are the values tabulated, with the rod
//! geometry, by B. Banerjee's compilation of Taylor-test data (the Utah
//! data set `HighRateExptData`, `TaylorData/MATLAB/plotOFHCCu.m`, function
//! `zerilliData`, noted there as Johnson & Cook's tests, the 190 m/s profile
//! digitised from Zerilli & Armstrong, J. Appl. Phys. 61 (1987) 1816–1825,
//! p. 1822) and used in Banerjee, *An evaluation of plastic flow stress
//! models for the simulation of high-temperature and high-strain-rate
//! deformation of metals*, arXiv cond-mat/0512466 (2005). The 1983 paper
//! itself was not at hand to read the numbers off its figure.
//!
//! # The model
//!
//! A quarter of the rod (x, y ≥ 0; symmetry planes x = 0 and y = 0 through
//! the axis z) on the frictionless rigid wall z = 0 (the grid's normal
//! velocity is zero on and beyond the face, the tangential velocity free),
//! explicit MPM (MUSL, uGIMP, 2 particles per cell per direction), J2
//! plasticity with the Johnson–Cook flow stress above, no damage, the
//! library's Mie–Grüneisen copper for the pressure. See
//! `docs/physics/mpm/taylor.md`.
//!
//! # What is measured
//!
//! Each particle stands for the cube of side h = V₀^(1/3) (V₀ its initial
//! volume: the sub-cell the generator filled) centred on x_p and deformed
//! by F_p; its extent along a unit vector n is half the width of that
//! parallelepiped along n, ½ h ‖F_pᵀ n‖₁ (the support function of
//! F_p [−h/2, h/2]³). Then
//!
//! - final length L_f = max_p (z_p + ½ h ‖F_pᵀ e_z‖₁): the rear face's
//!   height above the wall;
//! - final diameter D_f = 2 max_p (r_p + ½ h ‖F_pᵀ e_r‖₁), r_p = √(x² + y²),
//!   e_r = (x, y, 0)/r_p: the widest point of the rod, which for a Taylor
//!   mushroom is the foot on the wall (`TaylorResult::widest_at` reports
//!   the height of the particle that sets it);
//! - the profile r(z): the same radial extent, maximised over the particles
//!   whose centres fall in each slice of height h (slices without a
//!   particle are left out).

use brisance_compose::build::build_section;
use brisance_compose::config::BoundaryConfig;
use brisance_compose::{load_str, run::advance_to, LoadedScenario};
use brisance_constitutive::elastic_plastic::PLASTIC_STRAIN_INDEX;
use brisance_core::Solver;
use brisance_mpm::{MpmSolver, Particles};

/// The V-TAYLOR scenario file.
pub const TAYLOR3D_CONFIG: &str = include_str!("../../../configs/taylor3d.ron");

/// Cells across the rod's radius in `configs/taylor3d.ron` as shipped.
pub const CONFIG_CELLS_ACROSS_RADIUS: usize = 12;

/// One published cylinder-impact (Taylor) test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TaylorTest {
    /// Initial length L₀, m.
    pub length: f64,
    /// Initial diameter D₀, m.
    pub diameter: f64,
    /// Impact velocity, m/s.
    pub velocity: f64,
    /// Measured final length over the initial, L_f/L₀.
    pub final_length_ratio: f64,
    /// Measured foot diameter over the initial, D_f/D₀.
    pub final_diameter_ratio: f64,
    /// Where the numbers come from.
    pub source: &'static str,
}

impl TaylorTest {
    /// Final length L_f, m.
    pub fn final_length(&self) -> f64 {
        self.final_length_ratio * self.length
    }

    /// Final (foot) diameter D_f, m.
    pub fn final_diameter(&self) -> f64 {
        self.final_diameter_ratio * self.diameter
    }
}

/// The OFHC copper cylinder-impact test at 190 m/s of Johnson & Cook (1983)
/// (module documentation).
pub const JOHNSON_COOK_1983_OFHC_190: TaylorTest = TaylorTest {
    length: 0.0254,
    diameter: 0.00762,
    velocity: 190.0,
    final_length_ratio: 0.638,
    final_diameter_ratio: 1.78,
    source: "Johnson & Cook (1983), Proc. 7th Int. Symp. Ballistics 541–547, OFHC copper \
             cylinder-impact test; Lf/L0 and Df/D0 as tabulated in Banerjee's Taylor-test \
             compilation (HighRateExptData, plotOFHCCu.m; Zerilli & Armstrong, J. Appl. Phys. \
             61 (1987) 1816)",
};

/// Final shape of the rod from its particles (module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct RodShape {
    /// Final length L_f, m.
    pub length: f64,
    /// Final (widest) diameter D_f, m.
    pub diameter: f64,
    /// Height of the particle centre that sets D_f, m.
    pub widest_at: f64,
    /// Slice centres z, m (slices of height h from the wall that hold a
    /// particle).
    pub profile_z: Vec<f64>,
    /// Largest radial extent in each slice, m.
    pub profile_r: Vec<f64>,
}

/// Half the width of the cube of side `h`, deformed by `f` (row-major),
/// along the unit vector `n`: ½ h ‖Fᵀn‖₁.
pub fn half_extent(f: &[f64; 9], h: f64, n: [f64; 3]) -> f64 {
    (0..3)
        .map(|j| (n[0] * f[j] + n[1] * f[3 + j] + n[2] * f[6 + j]).abs())
        .sum::<f64>()
        * 0.5
        * h
}

/// Measures the rod (module documentation) from its particles; the wall is
/// the plane z = 0 and the axis the line x = y = 0. Errors on an empty set.
pub fn rod_shape(particles: &Particles) -> Result<RodShape, String> {
    let side = |p: usize| particles.initial_volume[p].cbrt();
    let radial = |p: usize| {
        let [x, y, _] = particles.position[p];
        let r = x.hypot(y);
        let e = if r > 0.0 {
            [x / r, y / r, 0.0]
        } else {
            [1.0, 0.0, 0.0]
        };
        r + half_extent(&particles.deformation_gradient[p], side(p), e)
    };
    measure_rod(particles, 2, side, radial)
}

/// The rod's measures from each particle's side `side(p)` (of its
/// undeformed square or cube), its outermost radial face `radial(p)` and
/// the axial coordinate `axis` (the wall at 0): the highest face, the
/// widest face and the profile in slices of the smallest side.
fn measure_rod(
    particles: &Particles,
    axis: usize,
    side: impl Fn(usize) -> f64,
    radial: impl Fn(usize) -> f64,
) -> Result<RodShape, String> {
    if particles.is_empty() {
        return Err("no particles to measure".into());
    }
    let n = particles.len();
    let up: [f64; 3] = std::array::from_fn(|d| if d == axis { 1.0 } else { 0.0 });
    let top = (0..n)
        .map(|p| {
            particles.position[p][axis]
                + half_extent(&particles.deformation_gradient[p], side(p), up)
        })
        .fold(f64::NEG_INFINITY, f64::max);
    // Widest particle; ties go to the lowest index, so the result does not
    // depend on anything but the particle order.
    let (widest, radius) =
        (0..n)
            .map(|p| (p, radial(p)))
            .fold((0, f64::NEG_INFINITY), |best, (p, r)| {
                if r > best.1 {
                    (p, r)
                } else {
                    best
                }
            });
    let slice = (0..n).map(&side).fold(f64::INFINITY, f64::min);
    let slices = (top / slice).ceil().max(1.0) as usize;
    let mut largest = vec![f64::NEG_INFINITY; slices];
    for p in 0..n {
        let k = ((particles.position[p][axis] / slice).floor().max(0.0) as usize).min(slices - 1);
        largest[k] = largest[k].max(radial(p));
    }
    let (profile_z, profile_r) = largest
        .iter()
        .enumerate()
        .filter(|(_, r)| r.is_finite())
        .map(|(k, r)| ((k as f64 + 0.5) * slice, *r))
        .unzip();
    Ok(RodShape {
        length: top,
        diameter: 2.0 * radius,
        widest_at: particles.position[widest][axis],
        profile_z,
        profile_r,
    })
}

/// Result of one V-TAYLOR run.
#[derive(Debug, Clone, PartialEq)]
pub struct TaylorResult {
    /// Cells across the rod's radius.
    pub cells_across_radius: usize,
    /// Cell size Δx = R/`cells_across_radius`, m.
    pub cell_size: f64,
    /// Particles in the quarter rod.
    pub particles: usize,
    /// Steps taken.
    pub steps: u64,
    /// End time, s.
    pub end_time: f64,
    /// The undeformed rod's length by the same measure (L₀ up to round-off
    /// when L₀ is a whole number of particle heights), m.
    pub initial_length: f64,
    /// The undeformed rod's diameter by the same measure (D₀ up to the
    /// staircase of the particles on the curved surface), m.
    pub initial_diameter: f64,
    /// The rod's shape at the end.
    pub shape: RodShape,
    /// Kinetic energy at the end over the initial.
    pub kinetic_energy_ratio: f64,
    /// Particle mass over the exact quarter-rod mass ρ π R² L₀ / 4, minus 1.
    pub mass_error: f64,
    /// Relative change of the total (kinetic + internal) energy.
    pub energy_change: f64,
    /// Largest equivalent plastic strain.
    pub max_plastic_strain: f64,
    /// Largest temperature, K.
    pub max_temperature: f64,
}

/// Rod radius R = D₀/2 of the test, m.
fn rod_radius() -> f64 {
    0.5 * JOHNSON_COOK_1983_OFHC_190.diameter
}

/// `configs/taylor3d.ron` with `cells_across_radius` cells across the rod's
/// radius (Δx = R/n): ⌈2.5 n⌉ cells in x and y (room for a foot of radius
/// 2.5 R) and ⌈L₀/Δx⌉ + 2 cells in z, the domain upper corner set to
/// match; `end` s of simulated time; then the `--set`-style `extra`
/// overrides (`PATH=VALUE`, for sensitivity studies).
pub fn taylor_scenario(
    cells_across_radius: usize,
    end: f64,
    extra: &[String],
) -> Result<LoadedScenario, String> {
    if cells_across_radius == 0 {
        return Err("cells_across_radius must be at least 1".into());
    }
    let dx = rod_radius() / cells_across_radius as f64;
    let across = (2.5 * cells_across_radius as f64).ceil() as usize;
    // The rod's length in cells, rounded to the nearest when it is within
    // rounding of a whole number (L₀/Δx = 20n/3).
    let along_f = JOHNSON_COOK_1983_OFHC_190.length / dx;
    let along = if (along_f - along_f.round()).abs() < 1e-9 {
        along_f.round() as usize
    } else {
        along_f.ceil() as usize
    } + 2;
    let (w, h) = (across as f64 * dx, along as f64 * dx);
    let mut sets = vec![
        format!("domain.cells=({across},{across},{along})"),
        format!("domain.upper=({w:e},{w:e},{h:e})"),
        format!("time.end={end:e}"),
    ];
    sets.extend_from_slice(extra);
    load_str("configs/taylor3d.ron", TAYLOR3D_CONFIG, &sets).map_err(|e| e.to_string())
}

/// Builds the MPM solver of a one-region `Mpm` scenario by the `Mpm`
/// pipeline's own builder (`brisance run`'s path,
/// [`brisance_compose::build::build_section`]), as an [`MpmSolver`] so its
/// particles can be measured. The rod needs one initial region (its
/// material's particles are the rod) and `Wall`, `Reflective` or
/// `Outflow` faces.
pub fn taylor_solver(loaded: &LoadedScenario) -> Result<MpmSolver, String> {
    let s = &loaded.scenario;
    let Some(mpm) = s.pipeline.section::<brisance_couple::MpmConfig>() else {
        return Err("pipeline: V-TAYLOR needs the Mpm pipeline".into());
    };
    if s.initial.len() != 1 {
        return Err(format!(
            "initial: V-TAYLOR expects one initial region, the scenario has {}",
            s.initial.len()
        ));
    }
    let faces = s.boundaries.faces();
    if let Some((face, bc)) = faces.iter().find(|(_, bc)| {
        !matches!(
            bc,
            BoundaryConfig::Wall | BoundaryConfig::Reflective | BoundaryConfig::Outflow
        )
    }) {
        return Err(format!(
            "boundaries.{face}: the Taylor bar takes `Wall`, `Reflective` or `Outflow` faces, not `{}`",
            bc.name()
        ));
    }
    build_section(mpm, s).map_err(|e| loaded.locate(e).to_string())
}

/// `configs/taylor3d.ron` on an axisymmetric (r, z) grid with
/// `cells_across_radius` cells across the rod's radius: the same rod, the
/// same copper and solver options, as the (r, z) half-plane (x = r, y the
/// rod's axis with the wall at y = 0), ⌈2.5 n⌉ × (⌈L₀/Δx⌉ + 2) cells,
/// `end` s; then the `--set`-style `extra` overrides.
pub fn taylor_rz_scenario(
    cells_across_radius: usize,
    end: f64,
    extra: &[String],
) -> Result<LoadedScenario, String> {
    let three_d = taylor_scenario(cells_across_radius, end, &[])?;
    let [across, _, along] = three_d.scenario.domain.cells;
    let dx = rod_radius() / cells_across_radius as f64;
    let (w, h) = (across as f64 * dx, along as f64 * dx);
    let test = JOHNSON_COOK_1983_OFHC_190;
    let mut sets = vec![
        "domain.geometry=Axisymmetric".to_string(),
        format!("domain.cells=({across},{along},1)"),
        format!("domain.upper=({w:e},{h:e},{dx:e})"),
        format!("time.end={end:e}"),
        format!(
            "initial.0.region=Box(min:(0.0,0.0,0.0),max:({:e},{:e},{dx:e}))",
            rod_radius(),
            test.length
        ),
        format!("initial.0.state.velocity=(0.0,{:e},0.0)", -test.velocity),
    ];
    sets.extend_from_slice(extra);
    load_str("configs/taylor3d.ron", TAYLOR3D_CONFIG, &sets).map_err(|e| e.to_string())
}

/// The rod's shape on an (r, z) grid, measured as [`rod_shape`] does in
/// 3D: each particle is the square of its ring's initial cross-section
/// A₀ = V₀ F_θθ / (2π r), deformed by its in-plane F; L_f is the highest
/// face above the wall (y), D_f twice the largest radial face (x).
pub fn rod_shape_rz(particles: &Particles) -> Result<RodShape, String> {
    let side = |p: usize| {
        let f = &particles.deformation_gradient[p];
        (particles.initial_volume[p] * f[8]
            / (2.0 * std::f64::consts::PI * particles.position[p][0]))
            .sqrt()
    };
    let radial = |p: usize| {
        particles.position[p][0]
            + half_extent(&particles.deformation_gradient[p], side(p), [1.0, 0.0, 0.0])
    };
    measure_rod(particles, 1, side, radial)
}

/// V-TAYLOR on the axisymmetric (r, z) grid ([`taylor_rz_scenario`]): the
/// whole rod as rings, measured with [`rod_shape_rz`]; the mass error is
/// against the whole rod ρ π R² L₀.
pub fn taylor_rz_case(
    cells_across_radius: usize,
    end: f64,
    extra: &[String],
) -> Result<TaylorResult, String> {
    let scenario = taylor_rz_scenario(cells_across_radius, end, extra)?;
    let test = JOHNSON_COOK_1983_OFHC_190;
    run_rod(
        &scenario,
        cells_across_radius,
        rod_radius(),
        test.length,
        end,
    )
}

/// Σ ½ m |v|², J.
fn kinetic_energy(p: &Particles) -> f64 {
    p.mass
        .iter()
        .zip(&p.velocity)
        .map(|(m, v)| 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]))
        .sum()
}

/// Runs V-TAYLOR with `cells_across_radius` cells across the rod's radius
/// to `end` s, with the `extra` overrides of [`taylor_scenario`], and
/// measures the rod (module documentation).
pub fn taylor_case(
    cells_across_radius: usize,
    end: f64,
    extra: &[String],
) -> Result<TaylorResult, String> {
    let scenario = taylor_scenario(cells_across_radius, end, extra)?;
    let test = JOHNSON_COOK_1983_OFHC_190;
    run_rod(
        &scenario,
        cells_across_radius,
        rod_radius(),
        test.length,
        end,
    )
}

/// Runs the one-rod `scenario` (radius `radius`, length `length`, m) to
/// `end` s and measures it; `cells_across_radius` is recorded with the
/// cell size radius/`cells_across_radius`. A Cartesian scenario is the
/// quarter rod ([`rod_shape`], mass against ρπR²L₀/4), an axisymmetric one
/// the whole rod as rings ([`rod_shape_rz`], mass against ρπR²L₀).
fn run_rod(
    loaded: &LoadedScenario,
    cells_across_radius: usize,
    radius: f64,
    length: f64,
    end: f64,
) -> Result<TaylorResult, String> {
    let mut solver = taylor_solver(loaded)?;
    let scenario = &loaded.scenario;
    let rho = scenario.initial[0].state.density;
    let axisymmetric = scenario.domain.geometry.is_axisymmetric();
    let measure = if axisymmetric {
        rod_shape_rz
    } else {
        rod_shape
    };
    let share = if axisymmetric { 1.0 } else { 0.25 };
    let exact_mass = rho * std::f64::consts::PI * radius.powi(2) * length * share;
    let initial = measure(solver.particles())?;
    let ke0 = kinetic_energy(solver.particles());
    let e0 = solver.conservation_totals().energy;
    let steps = advance_to(&mut solver, end).map_err(|e| e.to_string())?;
    let ps = solver.particles();
    let max_plastic_strain = (0..ps.len())
        .map(|p| ps.history_of(p)[PLASTIC_STRAIN_INDEX])
        .fold(0.0, f64::max);
    let max_temperature = ps.temperature.iter().copied().fold(0.0, f64::max);
    Ok(TaylorResult {
        cells_across_radius,
        cell_size: radius / cells_across_radius as f64,
        particles: ps.len(),
        steps,
        end_time: solver.time(),
        initial_length: initial.length,
        initial_diameter: initial.diameter,
        shape: measure(ps)?,
        kinetic_energy_ratio: kinetic_energy(ps) / ke0,
        mass_error: ps.total_mass() / exact_mass - 1.0,
        energy_change: (solver.conservation_totals().energy - e0) / e0,
        max_plastic_strain,
        max_temperature,
    })
}

/// The elastic, linearly hardening copper bar on a rigid frictionless wall,
/// a standard check of impact codes (Wilkins & Guinan, J. Appl. Phys. 44
/// (1973) 1200; the benchmark of A. Kamoulakos, *A simple benchmark for
/// impact*, NAFEMS Benchmark (1990)): L₀ = 32.4 mm, R₀ = 3.2 mm, 227 m/s,
/// ρ = 8930 kg/m³, E = 117 GPa, ν = 0.35, σ_y = 400 MPa, tangent modulus
/// E_t = 100 MPa, 80 µs. No rate, no temperature: it tests the solver
/// (kinematics, wall, shape functions, radial return) apart from the
/// Johnson–Cook model. See `docs/physics/mpm/taylor.md` for the reference
/// values.
pub mod bilinear_bar {
    /// Rod length L₀, m.
    pub const LENGTH: f64 = 0.0324;
    /// Rod radius R₀, m.
    pub const RADIUS: f64 = 0.0032;
    /// Impact velocity, m/s.
    pub const VELOCITY: f64 = 227.0;
    /// Density, kg/m³.
    pub const DENSITY: f64 = 8930.0;
    /// Young's modulus, Pa.
    pub const YOUNG: f64 = 117.0e9;
    /// Poisson's ratio.
    pub const POISSON: f64 = 0.35;
    /// Initial yield stress, Pa.
    pub const YIELD: f64 = 400.0e6;
    /// Tangent modulus of the uniaxial stress–strain curve, Pa.
    pub const TANGENT: f64 = 100.0e6;
    /// Simulated time, s.
    pub const END: f64 = 80.0e-6;
    /// Final length of the finite-element reference solutions, m (21.42 to
    /// 21.47 mm quoted).
    pub const REFERENCE_LENGTH: f64 = 21.45e-3;
    /// Final mushroom radius of the finite-element reference solutions, m
    /// (7.0 to 7.13 mm quoted).
    pub const REFERENCE_RADIUS: f64 = 7.07e-3;

    /// Shear modulus G = E/(2(1 + ν)), Pa.
    pub fn shear_modulus() -> f64 {
        YOUNG / (2.0 * (1.0 + POISSON))
    }

    /// Bulk modulus K = E/(3(1 − 2ν)), Pa.
    pub fn bulk_modulus() -> f64 {
        YOUNG / (3.0 * (1.0 - 2.0 * POISSON))
    }

    /// Plastic modulus H = E E_t/(E − E_t): σ_y = σ₀ + H ε_p.
    pub fn plastic_modulus() -> f64 {
        YOUNG * TANGENT / (YOUNG - TANGENT)
    }
}

/// `configs/taylor3d.ron` turned into the bilinear bar
/// ([`bilinear_bar`]) with `cells_across_radius` cells across R₀ (3 n
/// cells across, room for a foot of 3 R₀; L₀/Δx + 2 cells along, rounded
/// up), then the `extra` overrides. The flow stress is the Johnson–Cook
/// form with n = 1, B = H, C = 0 and T_room = 300 K, the rod's constant
/// temperature (no plastic heating: T* = 0 exactly); the pressure a
/// Mie–Grüneisen EOS with C₀ = √(K/ρ) and S, Γ₀ of 10⁻⁶ (the EOS form wants
/// them positive), which is K (1 − ρ₀/ρ) to within 10⁻⁶ of the volume
/// strain.
pub fn bilinear_bar_scenario(
    cells_across_radius: usize,
    extra: &[String],
) -> Result<LoadedScenario, String> {
    use bilinear_bar as b;
    if cells_across_radius == 0 {
        return Err("cells_across_radius must be at least 1".into());
    }
    let dx = b::RADIUS / cells_across_radius as f64;
    let across = 3 * cells_across_radius;
    let along = (b::LENGTH / dx - 1e-9).ceil() as usize + 2;
    let (w, h) = (across as f64 * dx, along as f64 * dx);
    let c0 = (b::bulk_modulus() / b::DENSITY).sqrt();
    let mut sets = vec![
        format!("domain.cells=({across},{across},{along})"),
        format!("domain.upper=({w:e},{w:e},{h:e})"),
        format!("time.end={:e}", b::END),
        format!(
            "initial.0.region=Cylinder(base:(0.0,0.0,0.0),axis:(0.0,0.0,1.0),radius:{:e},length:{:e})",
            b::RADIUS,
            b::LENGTH
        ),
        format!("initial.0.state.velocity=(0.0,0.0,{:e})", -b::VELOCITY),
        format!("initial.0.state.density={:e}", b::DENSITY),
        format!("materials.copper.model.shear_modulus={:e}", b::shear_modulus()),
        format!(
            "materials.copper.model.flow_stress=JohnsonCook(a:{:e},b:{:e},n:1.0,c:0.0,m:1.0,eps_dot0:1.0,t_room:300.0,t_melt:1356.0)",
            b::YIELD,
            b::plastic_modulus()
        ),
        format!(
            "materials.copper.model.pressure=Eos(MieGruneisenLinear(c0:{c0:e},s:1.0e-6,gamma0:1.0e-6,rho0:{:e},cv:383.0,t0:300.0))",
            b::DENSITY
        ),
        "materials.copper.model.taylor_quinney=0.0".to_string(),
    ];
    sets.extend_from_slice(extra);
    load_str("configs/taylor3d.ron", TAYLOR3D_CONFIG, &sets).map_err(|e| e.to_string())
}

/// Runs the bilinear bar ([`bilinear_bar_scenario`]) and measures it as
/// V-TAYLOR measures its rod; the mushroom radius is half the diameter.
pub fn bilinear_bar_case(
    cells_across_radius: usize,
    extra: &[String],
) -> Result<TaylorResult, String> {
    use bilinear_bar as b;
    let scenario = bilinear_bar_scenario(cells_across_radius, extra)?;
    run_rod(&scenario, cells_across_radius, b::RADIUS, b::LENGTH, b::END)
}

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_constitutive::MaterialModel;
    use brisance_mpm::ParticleInit;

    fn particle(ps: &mut Particles, x: [f64; 3], f: [f64; 9], volume: f64) {
        let init = ParticleInit {
            position: x,
            mass: 1.0,
            volume,
            deformation_gradient: f,
            ..Default::default()
        };
        let history = vec![0.0; ps.history_stride()];
        ps.push(&init, &history).unwrap();
    }

    const IDENTITY: [f64; 9] = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];

    #[test]
    fn half_extent_is_the_support_of_the_deformed_cube() {
        // Undeformed: half the side along any axis.
        assert_eq!(half_extent(&IDENTITY, 0.2, [0.0, 0.0, 1.0]), 0.1);
        // Stretched by 2 along x, squashed by 1/2 along z.
        let f = [2.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.5];
        assert_eq!(half_extent(&f, 0.2, [1.0, 0.0, 0.0]), 0.2);
        assert_eq!(half_extent(&f, 0.2, [0.0, 0.0, 1.0]), 0.05);
        // Simple shear x += 0.5 z: the cube's x-extent is 0.1 (1 + 0.5).
        let shear = [1.0, 0.0, 0.5, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        assert!((half_extent(&shear, 0.2, [1.0, 0.0, 0.0]) - 0.15).abs() < 1e-15);
        // Unit cube rotated 45° about z: its x-width is √2.
        let c = std::f64::consts::FRAC_1_SQRT_2;
        let rot = [c, -c, 0.0, c, c, 0.0, 0.0, 0.0, 1.0];
        assert!((half_extent(&rot, 1.0, [1.0, 0.0, 0.0]) - c).abs() < 1e-15);
    }

    #[test]
    fn rod_shape_takes_the_outermost_faces_and_slices_the_profile() {
        let mut ps = Particles::new(0);
        // h = 0.1 for every particle (V₀ = 1e-3).
        let v = 1e-3;
        particle(&mut ps, [0.05, 0.05, 0.05], IDENTITY, v);
        // A foot particle at r = 0.5, stretched ×2 radially (along x).
        let f = [2.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.5];
        particle(&mut ps, [0.5, 0.0, 0.05], f, v);
        // A diagonal particle at r = 0.3√2 = 0.4243, undeformed: its radial
        // extent along (1, 1, 0)/√2 is 0.05·√2.
        particle(&mut ps, [0.3, 0.3, 0.15], IDENTITY, v);
        // The rear particle at z = 0.95, squashed axially to 0.8.
        let g = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.8];
        particle(&mut ps, [0.05, 0.0, 0.95], g, v);
        let s = rod_shape(&ps).unwrap();
        assert!((s.length - (0.95 + 0.04)).abs() < 1e-12, "{}", s.length);
        assert!((s.diameter - 2.0 * 0.6).abs() < 1e-12, "{}", s.diameter);
        assert_eq!(s.widest_at, 0.05);
        // Slices of height 0.1 up to 0.99: 10 of them, particles in the
        // first, second and last.
        assert_eq!(s.profile_z.len(), 3);
        for (z, want) in s.profile_z.iter().zip([0.05, 0.15, 0.95]) {
            assert!((z - want).abs() < 1e-12, "{z} vs {want}");
        }
        assert!((s.profile_r[0] - 0.6).abs() < 1e-12);
        let diag = 0.3 * 2f64.sqrt() + 0.05 * 2f64.sqrt();
        assert!((s.profile_r[1] - diag).abs() < 1e-12, "{}", s.profile_r[1]);
        assert!((s.profile_r[2] - 0.1).abs() < 1e-12);
        assert!(rod_shape(&Particles::new(0)).is_err());
    }

    #[test]
    fn the_shipped_config_is_the_twelve_cell_scenario() {
        let shipped = load_str("configs/taylor3d.ron", TAYLOR3D_CONFIG, &[])
            .unwrap()
            .scenario;
        let built = taylor_scenario(CONFIG_CELLS_ACROSS_RADIUS, shipped.time.end, &[])
            .unwrap()
            .scenario;
        assert_eq!(built.domain.cells, shipped.domain.cells);
        for d in 0..3 {
            let (a, b) = (built.domain.upper[d], shipped.domain.upper[d]);
            assert!((a - b).abs() <= 1e-12 * b, "upper[{d}]: {a} vs {b}");
        }
        assert_eq!(built.materials, shipped.materials);
        assert_eq!(built.initial, shipped.initial);
    }

    #[test]
    fn a_scenario_that_does_not_build_names_the_file_line_and_field() {
        // A particle gauge over a box of air, away from the rod: the build
        // refuses it, at the gauge's place in the text after the overrides.
        let set = ["outputs.particle_gauges=[(name: \"air\", region: Box(min: (0.008, 0.008, 0.03), \
                    max: (0.009, 0.009, 0.031)), material: \"copper\", quantities: [MeanVelocity])]"
            .to_string()];
        let loaded = taylor_scenario(2, 1e-6, &set).unwrap();
        let e = taylor_solver(&loaded).unwrap_err();
        let at = loaded.text.find("region: Box(min: (0.008").unwrap();
        let line = 1 + loaded.text[..at].matches('\n').count();
        assert!(
            e.starts_with(&format!("configs/taylor3d.ron:{line}:")),
            "{e}"
        );
        assert!(e.contains("`outputs.particle_gauges.0.region`"), "{e}");
    }

    #[test]
    fn the_anti_locking_option_is_off_as_shipped_and_reaches_the_solver() {
        use brisance_mpm::AntiLocking;
        let off = taylor_solver(&taylor_scenario(2, 1e-6, &[]).unwrap()).unwrap();
        assert_eq!(off.options().anti_locking, AntiLocking::Off);
        let set = ["pipeline.anti_locking=FBar".to_string()];
        let on = taylor_solver(&taylor_scenario(2, 1e-6, &set).unwrap()).unwrap();
        assert_eq!(on.options().anti_locking, AntiLocking::FBar);
    }

    #[test]
    fn the_rod_uses_the_published_johnson_cook_constants_and_the_library_copper() {
        use brisance_constitutive::{FlowStress, PressureModel};
        let s = taylor_scenario(3, 1e-6, &[]).unwrap().scenario;
        let copper = &s.materials["copper"];
        let Some(MaterialModel::ElasticPlastic(ep)) = &copper.model else {
            panic!("the rod is not ElasticPlastic");
        };
        assert_eq!(
            ep.flow_stress,
            FlowStress::ofhc_copper_johnson_cook_1983(),
            "Johnson & Cook (1983) OFHC copper"
        );
        assert!(ep.damage.is_none());
        // The library's copper, less its damage model.
        let library = brisance_compose::library::get("ofhc_copper").unwrap();
        let Some(MaterialModel::ElasticPlastic(mut lib)) = library.model.clone() else {
            panic!("the library copper is not ElasticPlastic");
        };
        lib.damage = None;
        assert_eq!(ep, &lib);
        let eos = library.eos.clone().unwrap();
        assert_eq!(ep.pressure, PressureModel::Eos(eos.clone()));
        assert_eq!(copper.eos.as_ref(), Some(&eos));
        let test = JOHNSON_COOK_1983_OFHC_190;
        assert_eq!(s.initial[0].state.velocity, [0.0, 0.0, -test.velocity]);
    }

    #[test]
    fn the_bilinear_bar_has_the_benchmark_material_and_geometry() {
        use bilinear_bar as b;
        // G = 117/2.7 GPa, K = 117/0.9 GPa, H = 117e9·1e8/(116.9e9).
        assert!((b::shear_modulus() - 43.333_333_333e9).abs() < 1.0);
        assert!((b::bulk_modulus() - 130.0e9).abs() < 1.0);
        assert!((b::plastic_modulus() - 100.085_543_2e6).abs() < 1.0);
        let loaded = bilinear_bar_scenario(8, &[]).unwrap();
        let s = &loaded.scenario;
        // Δx = 0.4 mm: L₀ = 81 Δx, 83 cells along, 24 across.
        assert_eq!(s.domain.cells, [24, 24, 83]);
        let Some(MaterialModel::ElasticPlastic(ep)) = &s.materials["copper"].model else {
            panic!("the bar is not ElasticPlastic");
        };
        assert_eq!(ep.shear_modulus, b::shear_modulus());
        assert_eq!(ep.taylor_quinney, 0.0);
        // σ_y = 400 MPa + H ε_p, whatever the rate, at the bar's 300 K.
        for (eps, rate) in [(0.0, 0.0), (0.5, 1e5), (2.0, 1e3)] {
            let want = b::YIELD + b::plastic_modulus() * eps;
            let got = ep.flow_stress.flow_stress(eps, rate, 300.0);
            assert!((got - want).abs() < 1e-6 * want, "{eps}: {got} vs {want}");
        }
        // Bulk response K (1 − ρ₀/ρ) to well within 1e-4 at 1 % compression.
        let rho = b::DENSITY / 0.99;
        let p = ep.pressure.pressure(0.0, 0.0, 0.0, rho, 0.0);
        let want = b::bulk_modulus() * (1.0 - b::DENSITY / rho);
        assert!((p - want).abs() < 1e-4 * want, "{p} vs {want}");
        assert_eq!(s.initial[0].state.velocity, [0.0, 0.0, -b::VELOCITY]);
        // The undeformed bar measures L₀ (81 particle pairs) and R₀ within
        // one particle width.
        let solver = taylor_solver(&loaded).unwrap();
        let shape = rod_shape(solver.particles()).unwrap();
        assert!((shape.length - b::LENGTH).abs() < 1e-12, "{}", shape.length);
        assert!((0.5 * shape.diameter - b::RADIUS).abs() <= 0.5 * 0.4e-3);
    }

    #[test]
    fn the_undeformed_rod_measures_its_initial_length_and_diameter() {
        // n = 3: Δx = 1.27 mm, L₀ = 20 Δx, h = Δx/2 = 0.635 mm.
        let solver = taylor_solver(&taylor_scenario(3, 1e-6, &[]).unwrap()).unwrap();
        let s = rod_shape(solver.particles()).unwrap();
        let test = JOHNSON_COOK_1983_OFHC_190;
        assert!((s.length - test.length).abs() < 1e-12, "{}", s.length);
        let h = 0.5 * rod_radius() / 3.0;
        assert!(
            (s.diameter - test.diameter).abs() <= h,
            "D {} vs D0 {} (h {h})",
            s.diameter,
            test.diameter
        );
    }
}
