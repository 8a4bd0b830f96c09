//! Two-species (products in air) solver tests and the outflow boundary test.

use brisance_core::Solver;
use brisance_eos::{IdealGas, Jwl};
use brisance_grid::Level;

use crate::{FdmBoundary, FdmOptions, FdmSolver, PrimitiveState, ProductsInAir};

type Mix = ProductsInAir<Jwl, IdealGas>;

fn mix() -> Mix {
    ProductsInAir::new(Jwl::tnt(), IdealGas::air()).unwrap()
}

fn line(n: usize, length: f64) -> Level {
    Level::new(
        [0.0; 3],
        [length, 1.0, 1.0],
        [n, 1, 1],
        [1, 1, 1],
        crate::sweep::GHOST,
    )
    .unwrap()
}

fn field(s: &impl Solver, name: &str) -> Vec<f64> {
    s.cell_data(&[name.to_string()]).unwrap().fields[0]
        .1
        .clone()
}

fn run_until(s: &mut impl Solver, t_end: f64) {
    while s.time() < t_end {
        let dt = s.stable_dt().unwrap().min(t_end - s.time());
        s.advance(dt).unwrap();
    }
}

/// A slab of products (x < 0.3 m) in air moving at 100 m/s through a
/// periodic 1 m tube at 1 bar, both at `rho_products` / `rho_air`.
fn advected_interface(rho_products: f64, rho_air: f64) -> FdmSolver<Mix> {
    FdmSolver::with_species(
        mix(),
        line(200, 1.0),
        [FdmBoundary::Periodic; 6],
        FdmOptions::default(),
        |x| {
            let inside = x[0] > 0.1 && x[0] < 0.4;
            let state = PrimitiveState {
                density: if inside { rho_products } else { rho_air },
                velocity: [100.0, 0.0, 0.0],
                pressure: 1.0e5,
            };
            (state, if inside { 1.0 } else { 0.0 })
        },
    )
    .unwrap()
}

/// Largest |p − 1 bar|/1 bar and |u − 100|/100 over the tube.
fn pressure_velocity_error(s: &impl Solver) -> (f64, f64) {
    let p = field(s, "pressure");
    let u = field(s, "velocity_x");
    let ep = p
        .iter()
        .fold(0.0f64, |m, p| m.max((p - 1.0e5).abs() / 1.0e5));
    let eu = u
        .iter()
        .fold(0.0f64, |m, u| m.max((u - 100.0).abs() / 100.0));
    (ep, eu)
}

/// The simpler mass-weighted pressure rule p = Y p_P(ρ, e) + (1 − Y) p_A(ρ, e),
/// to show that the interface test tells the rules apart.
#[derive(Debug)]
struct MassWeighted(Mix);

impl crate::GasLaw for MassWeighted {
    const SPECIES: bool = true;
    fn gas_pressure(&self, rho: f64, e: f64, y: f64) -> f64 {
        use brisance_core::Eos;
        y * self.0.products().pressure(rho, e) + (1.0 - y) * self.0.air().pressure(rho, e)
    }
    fn gas_sound_speed(&self, rho: f64, e: f64, y: f64) -> f64 {
        self.0.gas_sound_speed(rho, e, y)
    }
    fn gas_temperature(&self, rho: f64, e: f64, y: f64) -> f64 {
        self.0.gas_temperature(rho, e, y)
    }
    fn gas_energy(&self, rho: f64, p: f64, y: f64) -> Result<f64, brisance_core::EosError> {
        // Pure states only in this test: invert the component law.
        use brisance_core::Eos;
        if y > 0.5 {
            self.0.products().specific_internal_energy(rho, p)
        } else {
            self.0.air().specific_internal_energy(rho, p)
        }
    }
}

/// Interface spike criterion: |Δp|/p below 10⁻³ and |Δu|/u below 2·10⁻³
/// (a pressure spike of the kind Abgrall describes is of order 10⁻²).
const SPIKE_FREE_P: f64 = 1e-3;
const SPIKE_FREE_U: f64 = 2e-3;

#[test]
fn species_interface_at_equal_density_has_no_pressure_spike() {
    // Equal densities: the pressure-equilibrium rule keeps every convex
    // combination of the two states at 1 bar; what remains comes from
    // clipping Y to [0, 1] where Lax–Wendroff over- or undershoots.
    let mut s = advected_interface(1.2, 1.2);
    let m0 = s.products_mass();
    run_until(&mut s, 2.0e-3); // 0.2 m of travel
    let (ep, eu) = pressure_velocity_error(&s);
    eprintln!("equal-density interface: pressure error {ep:e}, velocity error {eu:e}");
    assert!(
        ep < SPIKE_FREE_P && eu < SPIKE_FREE_U,
        "pressure error {ep:e}, velocity error {eu:e}"
    );
    let y = field(&s, "products_mass_fraction");
    assert!(y.iter().all(|y| (0.0..=1.0).contains(y)));
    // The slab has moved: products now at x ∈ (0.3, 0.6).
    assert!(y[90] > 0.99 && y[40] < 0.01, "{} {}", y[90], y[40]);
    let dm = (s.products_mass() - m0).abs() / m0;
    eprintln!("equal-density interface: products mass change {dm:e}");
    assert!(dm < 1e-3, "products mass changed by {dm:e}");

    // The mass-weighted rule fails the same criterion.
    let mut naive = FdmSolver::with_species(
        MassWeighted(mix()),
        line(200, 1.0),
        [FdmBoundary::Periodic; 6],
        FdmOptions::default(),
        |x| {
            let inside = x[0] > 0.1 && x[0] < 0.4;
            let state = PrimitiveState {
                density: 1.2,
                velocity: [100.0, 0.0, 0.0],
                pressure: 1.0e5,
            };
            (state, if inside { 1.0 } else { 0.0 })
        },
    )
    .unwrap();
    run_until(&mut naive, 2.0e-3);
    let (ep, _) = pressure_velocity_error(&naive);
    eprintln!("mass-weighted rule: pressure error {ep:e}");
    assert!(ep > SPIKE_FREE_P, "mass-weighted rule error {ep:e}");
}

#[test]
fn species_interface_with_a_density_jump_stays_near_isobaric() {
    // Products twice as dense as the air: no conservative mass-fraction
    // scheme is exactly isobaric here (Abgrall 1996); the measured error is
    // written in docs/physics/fdm_mixture.md.
    let mut s = advected_interface(2.4, 1.2);
    let m0 = s.products_mass();
    run_until(&mut s, 2.0e-3);
    let (ep, eu) = pressure_velocity_error(&s);
    eprintln!("density-jump interface: pressure error {ep:e}, velocity error {eu:e}");
    assert!(
        ep < 0.02 && eu < 0.05,
        "pressure error {ep:e}, velocity error {eu:e}"
    );
    let y = field(&s, "products_mass_fraction");
    assert!(y.iter().all(|y| (0.0..=1.0).contains(y)));
    let dm = (s.products_mass() - m0).abs() / m0;
    eprintln!("products mass change {dm:e}");
    assert!(dm < 1e-3, "products mass changed by {dm:e}");
}

#[test]
fn products_against_air_shock_tube_conserves_and_bounds_y() {
    // Sod-like: hot products (10 bar, 5 kg/m³) expand into air (1 bar,
    // 1.2 kg/m³) between walls. Mass, energy and products mass are
    // conserved to round-off, Y stays in [0, 1], and the contact moves right.
    let mut s = FdmSolver::with_species(
        mix(),
        line(200, 1.0),
        [FdmBoundary::Reflective; 6],
        FdmOptions::default(),
        |x| {
            let left = x[0] < 0.5;
            let state = PrimitiveState {
                density: if left { 5.0 } else { 1.2 },
                velocity: [0.0; 3],
                pressure: if left { 1.0e6 } else { 1.0e5 },
            };
            (state, if left { 1.0 } else { 0.0 })
        },
    )
    .unwrap();
    let t0 = s.conservation_totals();
    let m0 = s.products_mass();
    run_until(&mut s, 4.0e-4);
    let t1 = s.conservation_totals();
    assert!((t1.mass - t0.mass).abs() < 1e-13 * t0.mass);
    assert!((t1.energy - t0.energy).abs() < 1e-12 * t0.energy);
    // ρY is conserved by the scheme; clipping Y to [0, 1] changes it.
    let dm = (s.products_mass() - m0).abs() / m0;
    eprintln!("shock tube: products mass change {dm:e}");
    assert!(dm < 1e-3, "products mass changed by {dm:e}");
    let y = field(&s, "products_mass_fraction");
    assert!(y.iter().all(|y| (0.0..=1.0).contains(y)));
    // The species interface (Y = ½) has moved downstream of x = 0.5.
    let front = y.iter().position(|&y| y < 0.5).unwrap();
    assert!(front > 105, "interface at cell {front}");
    let p = field(&s, "pressure");
    assert!(p.iter().all(|&p| p > 0.9e5 && p < 1.01e6));
}

#[test]
fn one_species_gas_carries_no_species_field() {
    let s = FdmSolver::new(
        IdealGas::air(),
        line(8, 1.0),
        [FdmBoundary::Outflow; 6],
        FdmOptions::default(),
        |_| PrimitiveState {
            density: 1.2,
            velocity: [0.0; 3],
            pressure: 1e5,
        },
    )
    .unwrap();
    assert!(!s.cell_field_names().contains(&"products_mass_fraction"));
    assert_eq!(s.products_mass(), 0.0);
    let e = s
        .cell_data(&["products_mass_fraction".to_string()])
        .unwrap_err()
        .to_string();
    assert!(e.contains("unknown field"), "{e}");
}

#[test]
fn mass_fraction_outside_unit_interval_is_refused() {
    let err = FdmSolver::with_species(
        mix(),
        line(8, 1.0),
        [FdmBoundary::Outflow; 6],
        FdmOptions::default(),
        |_| {
            (
                PrimitiveState {
                    density: 1.2,
                    velocity: [0.0; 3],
                    pressure: 1e5,
                },
                1.5,
            )
        },
    )
    .unwrap_err();
    assert!(err.to_string().contains("mass fraction"), "{err}");
}

#[test]
fn acoustic_pulse_leaves_through_outflow_boundaries() {
    // A right-going simple acoustic wave in air, δp = 1 kPa Gaussian of
    // width 0.05 m, u = δp/(ρc), ρ' = δp/c². Once it has crossed the right
    // face the tube must hold almost nothing of it.
    let gas = IdealGas::air();
    let (rho0, p0, dp): (f64, f64, f64) = (1.2, 1.0e5, 1.0e3);
    let c = (1.4 * p0 / rho0).sqrt();
    let mut s = FdmSolver::new(
        gas,
        line(200, 1.0),
        [FdmBoundary::Outflow; 6],
        FdmOptions::default(),
        |x| {
            let g = (-((x[0] - 0.5) / 0.05).powi(2)).exp();
            PrimitiveState {
                density: rho0 + dp * g / (c * c),
                velocity: [dp * g / (rho0 * c), 0.0, 0.0],
                pressure: p0 + dp * g,
            }
        },
    )
    .unwrap();
    // Peak reaches x = 1 after 0.5/c; the tail (3 widths) after 0.65/c;
    // wait until a reflection would have come back 0.35 m.
    run_until(&mut s, 1.0 / c);
    let p = field(&s, "pressure");
    let left = p.iter().fold(0.0f64, |m, p| m.max((p - p0).abs())) / dp;
    eprintln!("outflow: largest |p − p0|/δp left in the tube: {left:e}");
    assert!(left < 0.01, "reflection {left:e} of the pulse amplitude");
}

/// A 3D products sphere in air between walls, on a given patch layout.
fn products_sphere(layout: [usize; 3]) -> FdmSolver<Mix> {
    let level = Level::new(
        [0.0; 3],
        [0.12, 0.1, 0.08],
        [12, 10, 8],
        layout,
        crate::sweep::GHOST,
    )
    .unwrap();
    FdmSolver::with_species(
        mix(),
        level,
        [FdmBoundary::Reflective; 6],
        FdmOptions::default(),
        |x| {
            let r2 = (x[0] - 0.05).powi(2) + (x[1] - 0.04).powi(2) + (x[2] - 0.045).powi(2);
            let inside = r2 < 0.03f64.powi(2);
            let state = PrimitiveState {
                density: if inside { 20.0 } else { 1.2 },
                velocity: [0.0; 3],
                pressure: if inside { 2.0e7 } else { 1.0e5 },
            };
            (state, if inside { 1.0 } else { 0.0 })
        },
    )
    .unwrap()
}

#[test]
fn three_dimensional_products_run_is_split_independent_and_conservative() {
    let mut one = products_sphere([1, 1, 1]);
    let mut four = products_sphere([2, 2, 1]);
    let t0 = one.conservation_totals();
    let m0 = one.products_mass();
    for _ in 0..6 {
        let dt = one.stable_dt().unwrap();
        assert_eq!(dt.to_bits(), four.stable_dt().unwrap().to_bits());
        one.advance(dt).unwrap();
        four.advance(dt).unwrap();
    }
    let names: Vec<String> = one
        .cell_field_names()
        .iter()
        .map(|s| s.to_string())
        .collect();
    let (a, b) = (
        one.cell_data(&names).unwrap(),
        four.cell_data(&names).unwrap(),
    );
    for ((name, x), (_, y)) in a.fields.iter().zip(&b.fields) {
        assert!(
            x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits()),
            "{name} differs between patch layouts"
        );
    }
    let t1 = one.conservation_totals();
    assert!((t1.mass - t0.mass).abs() < 1e-13 * t0.mass);
    assert!((t1.energy - t0.energy).abs() < 1e-12 * t0.energy);
    // The products mass is changed by the clipping of Y only (measured
    // 6.2e-3 on this coarse, 16 : 1 density sphere; docs/physics/
    // fdm_mixture.md lists it as a limit), so it is reported, not bounded.
    let dm = (one.products_mass() - m0).abs() / m0;
    eprintln!("3D products sphere: products mass change {dm:e}");
    let y = field(&one, "products_mass_fraction");
    assert!(y.iter().all(|y| (0.0..=1.0).contains(y)));
    // The sphere has pushed air outward: some cells are mixed now.
    assert!(y.iter().any(|&y| y > 0.01 && y < 0.99));
}
