use super::*;
use crate::regions::RegionBox;
use brisance_constitutive::{MaterialModel, NullMaterial};
use brisance_core::Eos;
use brisance_eos::IdealGas;
use brisance_fdm::GHOST;
use brisance_fdm::{FdmBoundary, FdmOptions, PrimitiveState};
use brisance_grid::Level;
use brisance_mpm::{BulkViscosity, GridBoundary, MpmOptions, Particles, ShapeFunction};

const H: f64 = 0.002;
const P0: f64 = 1.0e5;
const RHO0: f64 = 1.225;

/// Shock-tube initial state: 5 bar, 4.9 kg/m³ for x < 0.1 m.
fn initial(x: [f64; 3]) -> PrimitiveState {
    let (density, pressure) = if x[0] < 0.1 { (4.9, 5.0e5) } else { (RHO0, P0) };
    PrimitiveState {
        density,
        velocity: [0.0; 3],
        pressure,
    }
}

/// The tube on an FDM grid: a wall at x = 0, `x_high` at the other end.
fn fdm_on(
    lower: [f64; 3],
    upper: [f64; 3],
    cells: [usize; 3],
    x_high: FdmBoundary,
) -> FdmSolver<IdealGas> {
    let level = Level::new(lower, upper, cells, [1, 1, 1], GHOST).unwrap();
    let mut bcs = [FdmBoundary::Outflow; 6];
    bcs[0] = FdmBoundary::Reflective;
    bcs[1] = x_high;
    FdmSolver::new(IdealGas::air(), level, bcs, FdmOptions::default(), initial).unwrap()
}

/// The coupled 1D tube: FDM (0, 0.3) m, MPM (0.29, 0.4) m, w = 5.
fn coupled() -> Cfdmp<IdealGas> {
    coupled_with(0.25)
}

/// [`coupled`] with the given `min_particle_mass`.
fn coupled_with(min_particle_mass: f64) -> Cfdmp<IdealGas> {
    coupled_inflow(min_particle_mass, false)
}

/// [`coupled`] with the given inflow rule.
fn coupled_inflow(min_particle_mass: f64, deposit: bool) -> Cfdmp<IdealGas> {
    coupled_of(min_particle_mass, deposit, 1, ShapeFunction::Linear)
}

/// [`coupled_inflow`] with `materials` MPM materials, air the first, and
/// the MPM's shape functions `shape`.
fn coupled_of(
    min_particle_mass: f64,
    deposit: bool,
    materials: usize,
    shape: ShapeFunction,
) -> Cfdmp<IdealGas> {
    let regions = BridgeRegions::from_boxes(
        RegionBox {
            lower: [0.0; 3],
            upper: [0.3, H, H],
        },
        RegionBox {
            lower: [0.29, 0.0, 0.0],
            upper: [0.4, H, H],
        },
        [H; 3],
        GHOST,
    )
    .unwrap();
    let (fg, _) = regions.fdm_grid(GHOST);
    let fdm = fdm_on(fg.origin, fg.upper(), fg.cells, FdmBoundary::Outflow);
    let (mg, _) = regions.mpm_grid();
    let first = regions.mpm.origin[0];
    let mpm = mpm_tube_of(
        mg,
        first,
        regions.mpm.upper()[0],
        GridBoundary::Outflow,
        materials,
        shape,
    );
    let m = RHO0 * H * H * H / 2.0;
    let air = IdealGas::air();
    Cfdmp::new(
        regions,
        fdm,
        mpm,
        GHOST,
        CfdmpOptions {
            air: MaterialId(0),
            products: None,
            gamma: air.gamma,
            existing_mass: m,
            activation_pressure: 1.05 * P0,
            activation_cells: 3,
            min_particle_mass,
            existing_volume: 0.0,
            deposit,
            donor_rings: 1,
            start_in_bridge: None,
        },
    )
    .unwrap()
}

/// Air particles (2 per cell) of the tube state between `from` and `to`
/// on the grid `g`, with `x_low` at the low end and a slip wall at the
/// high end; `materials` copies of the air model (material 0 the
/// particles') and the shape functions `shape`.
fn mpm_tube_of(
    g: brisance_core::UniformGridGeometry,
    from: f64,
    to: f64,
    x_low: GridBoundary,
    materials: usize,
    shape: ShapeFunction,
) -> MpmSolver {
    let level = Level::new(g.origin, g.upper(), g.cells, [1, 1, 1], 0).unwrap();
    let air = IdealGas::air();
    let mut ps = Particles::new(0);
    let ppc = 2;
    let cells = ((to - from) / H).round() as usize;
    for c in 0..cells {
        for s in 0..ppc {
            let x = from + (c as f64 + (s as f64 + 0.5) / ppc as f64) * H;
            let st = initial([x, 0.0, 0.0]);
            let (rho, p) = (st.density, st.pressure);
            let v = H * H * H / ppc as f64;
            ps.push(
                &ParticleInit {
                    position: [x, 0.5 * H, 0.5 * H],
                    mass: rho * v,
                    volume: v,
                    stress: [-p, -p, -p, 0.0, 0.0, 0.0],
                    specific_internal_energy: air.specific_internal_energy(rho, p).unwrap(),
                    ..Default::default()
                },
                &[],
            )
            .unwrap();
        }
    }
    MpmSolver::new(
        level,
        vec![MaterialModel::Null(NullMaterial::air()); materials],
        ps,
        MpmOptions {
            boundaries: [
                x_low,
                GridBoundary::Symmetry,
                GridBoundary::Free,
                GridBoundary::Free,
                GridBoundary::Free,
                GridBoundary::Free,
            ],
            bulk_viscosity: Some(BulkViscosity::default()),
            shape,
            ..Default::default()
        },
    )
    .unwrap()
}

fn sample(s: &impl Solver, x: f64) -> f64 {
    let mut out = Vec::new();
    s.sample([x, 0.5 * H, 0.5 * H], &["pressure".to_string()], &mut out)
        .unwrap();
    out[0]
}

/// (arrival time at half the jump, peak) of a pressure history.
fn arrival_and_peak(t: &[f64], p: &[f64]) -> (f64, f64) {
    let peak = p.iter().cloned().fold(f64::MIN, f64::max);
    let half = P0 + 0.5 * (peak - P0);
    let i = p.iter().position(|&x| x >= half).unwrap();
    let f = (half - p[i - 1]) / (p[i] - p[i - 1]);
    (t[i - 1] + f * (t[i] - t[i - 1]), peak)
}

/// After one MPM step of the tube, the storage indices of the
/// particles in the MPM cell of fictitious layer `l`, and the FDM cell
/// and MPM cell index of each layer.
fn layer_cells(c: &Cfdmp<IdealGas>) -> Vec<([usize; 3], usize)> {
    (0..c.layers)
        .map(|l| {
            let g = c.fictitious[l];
            (g, (g[0] as isize + c.mpm_shift) as usize)
        })
        .collect()
}

fn particles_in(c: &Cfdmp<IdealGas>, cell: usize) -> Vec<usize> {
    let mg = c.mpm.level().geometry;
    let ps = c.mpm.particles();
    (0..ps.len())
        .filter(|&p| mg.cell_containing(ps.position[p]).map(|q| q[0]) == Some(cell))
        .collect()
}

/// Eqs 31–36 by hand for the 1D tube's MPM cell `cell`: the two corner
/// nodes (N = ½) and the particles in the cell.
fn eqs_31_36(c: &Cfdmp<IdealGas>, cell: usize) -> [f64; 5] {
    let nodes = c.mpm.grid_nodes();
    let (mut m, mut p) = ([0.0; 2], [[0.0; 3]; 2]);
    for k in 0..2 {
        let n = nodes.lattice.index([(cell + k) as isize, 0, 0]).unwrap();
        m[k] = nodes.mass[n];
        p[k] = nodes.velocity_new[n].map(|v| v * m[k]);
    }
    let (mc, pc) = fictitious_mass_momentum(&m, &p, 0.5);
    let ps = c.mpm.particles();
    let mut e = 0.0;
    for q in particles_in(c, cell) {
        e += ps.mass[q] * ps.specific_internal_energy[q];
    }
    crate::bridge::fictitious_cell_state(mc, pc, e, H * H * H).unwrap()
}

fn conservative5(c: &Cfdmp<IdealGas>, g: [usize; 3]) -> [f64; 5] {
    let u = c.fdm.cell_conservative(g).unwrap();
    [u[0], u[1], u[2], u[3], u[4]]
}

#[test]
fn the_time_step_limit_is_the_smaller_step_s_part() {
    let mut c = coupled();
    // Before activation the FDM's step alone (step 1).
    c.active = false;
    let fdm = c.fdm.time_step_limit().unwrap();
    assert_eq!(Solver::time_step_limit(&c).as_deref(), Some(fdm.as_str()));
    // Active: the MPM's once a particle is faster than any cell.
    c.active = true;
    let ps = c.mpm.particles();
    let fast = ps.len();
    let twin = brisance_mpm::ParticleInit {
        position: ps.position[0],
        velocity: [3.0e3, 0.0, 0.0],
        mass: ps.mass[0],
        volume: ps.volume[0],
        specific_internal_energy: ps.specific_internal_energy[0],
        material: ps.material[0],
        ..Default::default()
    };
    c.mpm.insert_particles(&[twin]).unwrap();
    assert!(c.mpm.stable_dt().unwrap() < c.fdm.stable_dt().unwrap());
    let limit = Solver::time_step_limit(&c).unwrap();
    assert!(
        limit.starts_with(&format!("MPM particle {fast} ")),
        "{limit}"
    );
    assert_eq!(Some(limit), c.mpm.time_step_limit());
}

#[test]
fn an_empty_mpm_cell_gives_its_fictitious_cell_the_state_inside_it() {
    let mut c = coupled();
    let dt = c.mpm.stable_dt().unwrap().min(c.fdm.stable_dt().unwrap());
    c.mpm_step(dt).unwrap();
    let cells = layer_cells(&c);
    // Empty the MPM cell of layer 2 (the gas has left it).
    let gone = particles_in(&c, cells[2].1);
    assert_eq!(gone.len(), 2);
    c.mpm.remove_particles(&gone);
    // What the FDM sweep left there is not kept.
    c.fdm
        .set_cell_conservative(cells[2].0, [1.0, 0.0, 0.0, 0.0, -5.0, 0.0])
        .unwrap();
    c.update_fictitious_cells().unwrap();
    // Full cells: eqs 31–36 exactly, as before.
    for l in [0, 1, 3] {
        assert_eq!(
            conservative5(&c, cells[l].0),
            eqs_31_36(&c, cells[l].1),
            "layer {l}"
        );
    }
    // The empty one: layer 1's state (zero gradient), bit for bit.
    assert_eq!(conservative5(&c, cells[2].0), conservative5(&c, cells[1].0));
    let t = c.transport_totals();
    assert_eq!((t.zero_gradient, t.wall, t.supersonic_outflow), (1, 0, 0));
    // The FDM step leaves the fictitious cells as step 7 set them.
    c.active = true;
    let set: Vec<_> = cells.iter().map(|&(g, _)| conservative5(&c, g)).collect();
    c.fdm.advance(dt).unwrap();
    assert_ne!(conservative5(&c, cells[3].0), set[3]);
    c.set_fictitious_values().unwrap();
    for (l, &(g, _)) in cells.iter().enumerate() {
        assert_eq!(conservative5(&c, g), set[l], "layer {l}");
    }
}

#[test]
fn a_structure_in_the_fictitious_layers_is_a_reflecting_wall() {
    let mut c = coupled_of(0.25, false, 2, ShapeFunction::Linear);
    let dt = c.mpm.stable_dt().unwrap().min(c.fdm.stable_dt().unwrap());
    c.mpm_step(dt).unwrap();
    let cells = layer_cells(&c);
    // Layer 2's MPM cell: its air replaced by one particle of
    // material 1 (a structure) moving at 3 m/s.
    let gone = particles_in(&c, cells[2].1);
    c.mpm.remove_particles(&gone);
    let mg = c.mpm.level().geometry;
    let x = mg.cell_centre([cells[2].1, 0, 0]);
    c.mpm
        .insert_particles(&[ParticleInit {
            position: x,
            velocity: [3.0, 0.0, 0.0],
            mass: 1.0e-3,
            volume: H * H * H,
            material: MaterialId(1),
            ..Default::default()
        }])
        .unwrap();
    c.update_fictitious_cells().unwrap();
    let u = |l: usize| conservative5(&c, cells[l].0);
    // Layer 0: no structure in its neighbours, eqs 31–36.
    assert_eq!(u(0), eqs_31_36(&c, cells[0].1));
    // Layer 1: next to the structure, the air particles' own sums.
    let ps = c.mpm.particles();
    let (mut m, mut p, mut e) = (0.0, [0.0; 3], 0.0);
    for q in particles_in(&c, cells[1].1) {
        e += ps.mass[q] * ps.specific_internal_energy[q];
        m += ps.mass[q];
        for (pd, v) in p.iter_mut().zip(ps.velocity[q]) {
            *pd += ps.mass[q] * v;
        }
    }
    let own = crate::bridge::fictitious_cell_state(m, p, e, H * H * H).unwrap();
    assert_eq!(u(1), own);
    // Layers 2 and 3: the mirror images of layers 1 and 0 in a wall
    // moving at 3 m/s.
    let mirror = |v: [f64; 5]| {
        let w = crate::bridge::mirror_state([v[0], v[1], v[2], v[3], v[4], 0.0], 0, 3.0);
        [w[0], w[1], w[2], w[3], w[4]]
    };
    assert_eq!(u(2), mirror(u(1)));
    assert_eq!(u(3), mirror(u(0)));
    let t = c.transport_totals();
    assert_eq!((t.zero_gradient, t.wall), (0, 1));
}

#[test]
fn before_activation_the_mpm_region_past_the_fdm_grid_reads_the_mpm() {
    let c = coupled();
    assert!(!c.is_active());
    // x = 0.35 m: in the MPM region, past the fictitious cells (0.308
    // m), where the FDM grid has no cell. The MPM's air particles
    // start at p = P0, q = 0: −tr σ/3 = P0 exactly.
    assert_eq!(sample(&c, 0.35), P0);
    // A fictitious cell stays the FDM's.
    let mut fdm = Vec::new();
    c.fdm
        .sample(
            [0.305, 0.5 * H, 0.5 * H],
            &["pressure".to_string()],
            &mut fdm,
        )
        .unwrap();
    assert_eq!(sample(&c, 0.305), fdm[0]);
    // The cell data: the cell at 0.351 m from the MPM, P0.
    let d = c.cell_data(&["pressure".to_string()]).unwrap();
    let i = d
        .geometry
        .cell_containing([0.351, 0.5 * H, 0.5 * H])
        .unwrap();
    assert_eq!(d.fields[0].1[d.geometry.linear_index(i)], P0);
    // The shock tube's driver, x < 0.1 m, from the FDM: 5 bar.
    let i = d
        .geometry
        .cell_containing([0.05, 0.5 * H, 0.5 * H])
        .unwrap();
    assert_eq!(d.fields[0].1[d.geometry.linear_index(i)], 5.0e5);
}

#[test]
fn a_shock_passes_the_bridge_as_it_passes_a_pure_fdm_tube() {
    shock_through_the_bridge(ShapeFunction::Linear, false);
}

/// [`a_shock_passes_the_bridge_as_it_passes_a_pure_fdm_tube`] with cpGIMP
/// in the MPM region (its donor cells points, the pure MPM tube cpGIMP
/// too) and the inflow deposited (the pipeline's default), each deposit
/// moving its particle to the common centre of mass: the plateau within
/// 5 % of the pure cpGIMP tube (−1.9 %; −9.6 % with the particles left
/// in place, whose domains then overlap).
#[test]
fn with_cpgimp_a_shock_passes_the_bridge_as_it_passes_a_pure_fdm_tube() {
    shock_through_the_bridge(ShapeFunction::CpGimp, true);
}

/// The shock of [`initial`] through the bridge of [`coupled`] with the
/// MPM's shape functions `shape` and the inflow `deposit`ed or created,
/// against a pure FDM tube and a pure MPM tube of the same shape
/// functions.
fn shock_through_the_bridge(shape: ShapeFunction, deposit: bool) {
    let t_end = 7.0e-4;
    let (xf, xm) = (0.22, 0.33);
    let mut c = coupled_of(0.25, deposit, 1, shape);
    let m0 = c.mpm().conservation_totals().mass;
    let mut reference = fdm_on([0.0; 3], [0.4, H, H], [200, 1, 1], FdmBoundary::Reflective);
    let (mut tc, mut pf, mut pm) = (vec![0.0], vec![P0], vec![P0]);
    while c.time() < t_end {
        let dt = c.stable_dt().unwrap().min(t_end - c.time());
        c.advance(dt).unwrap();
        tc.push(c.time());
        pf.push(sample(c.fdm(), xf));
        pm.push(if c.is_active() {
            sample(c.mpm(), xm)
        } else {
            P0
        });
    }
    let (mut tr, mut rf, mut rm) = (vec![0.0], vec![P0], vec![P0]);
    while reference.time() < t_end {
        let dt = reference.stable_dt().unwrap().min(t_end - reference.time());
        reference.advance(dt).unwrap();
        tr.push(reference.time());
        rf.push(sample(&reference, xf));
        rm.push(sample(&reference, xm));
    }
    let whole = brisance_core::UniformGridGeometry {
        origin: [0.0; 3],
        spacing: [H; 3],
        cells: [200, 1, 1],
    };
    let mut pure = mpm_tube_of(whole, 0.0, 0.4, GridBoundary::Symmetry, 1, shape);
    let (mut tp, mut pp) = (vec![0.0], vec![P0]);
    while pure.time() < t_end {
        let dt = pure.stable_dt().unwrap().min(t_end - pure.time());
        pure.advance(dt).unwrap();
        tp.push(pure.time());
        pp.push(sample(&pure, xm));
    }
    let (tq, pq) = arrival_and_peak(&tp, &pp);
    eprintln!(
        "pure MPM gauge: arrival {tq:.4e} s, peak {pq:.4e} Pa; {} steps",
        tp.len() - 1
    );
    if std::env::var("BRIDGE_SERIES").is_ok() {
        for i in (0..tp.len()).step_by(10) {
            eprintln!("M {:.4e} {:.4e}", tp[i], pp[i]);
        }
    }
    let (ta, pa) = arrival_and_peak(&tc, &pm);
    let (tb, pb) = arrival_and_peak(&tr, &rm);
    let (tfa, pfa) = arrival_and_peak(&tc, &pf);
    let (tfb, pfb) = arrival_and_peak(&tr, &rf);
    // Mean pressure over the 150 µs after arrival (the MPM gauges
    // oscillate about it by ±10 % in the pure MPM run as well).
    let plateau = |t: &[f64], p: &[f64], from: f64| {
        let w: Vec<f64> = t
            .iter()
            .zip(p)
            .filter(|(&x, _)| x > from + 1.0e-5 && x < from + 1.6e-4)
            .map(|(_, &y)| y)
            .collect();
        w.iter().sum::<f64>() / w.len() as f64
    };
    let (qa, qq, qb) = (
        plateau(&tc, &pm, ta),
        plateau(&tp, &pp, tq),
        plateau(&tr, &rm, tb),
    );
    // After the shock has passed the FDM gauge, any wave reflected by
    // the interface shows as a departure from the reference there.
    let interp = |t: f64| {
        let i = tr.partition_point(|&x| x < t).clamp(1, tr.len() - 1);
        let f = (t - tr[i - 1]) / (tr[i] - tr[i - 1]);
        rf[i - 1] + f * (rf[i] - rf[i - 1])
    };
    let jump = pfb - P0;
    let reflected = tc
        .iter()
        .zip(&pf)
        .filter(|(&t, _)| t > tfb + 2.0e-5)
        .map(|(&t, &p)| (p - interp(t)).abs() / jump)
        .fold(0.0, f64::max);
    let tt = c.transport_totals();
    let pct = |a: f64, b: f64| 100.0 * (a - b) / b;
    eprintln!(
        "activated at {:?} s, {} steps, split FDM/MPM {:?} s\n\
         MPM gauge x = {xm} m: arrival {ta:.4e} s (pure MPM {tq:.4e}, FDM {tb:.4e}: {:+.2} %, {:+.2} %), \
         peak {pa:.4e} Pa (pure MPM {pq:.4e}, FDM {pb:.4e}: {:+.2} %, {:+.2} %), \
         plateau {qa:.4e} Pa (pure MPM {qq:.4e}, FDM {qb:.4e}: {:+.2} %, {:+.2} %)\n\
         FDM gauge x = {xf} m: arrival {:+.3} %, peak {:+.3} %, largest departure after the shock {:.3} % of the jump\n\
         created {} particles ({:.4e} kg), absorbed {}",
        c.activated_at(),
        c.steps(),
        c.split_seconds(),
        pct(ta, tq),
        pct(ta, tb),
        pct(pa, pq),
        pct(pa, pb),
        pct(qa, qq),
        pct(qa, qb),
        pct(tfa, tfb),
        pct(pfa, pfb),
        100.0 * reflected,
        tt.created,
        tt.into_mpm.mass,
        tt.absorbed,
    );
    assert!(c.activated_at().is_some());
    assert!(pb > 1.5 * P0, "the shock must reach the MPM gauge");
    // The interface leaves the MPM region's shock as the pure MPM run
    // has it, and reflects nothing visible into the FDM region.
    assert!(pct(ta, tq).abs() < 2.0);
    assert!(pct(qa, qq).abs() < 5.0);
    assert!(reflected < 0.01);
    // Mass booked by the transport is the MPM's mass change, to round-off.
    let m1 = c.mpm().conservation_totals().mass;
    let booked = m0 + tt.into_mpm.mass - tt.into_fdm.mass;
    assert!((m1 - booked).abs() < 1e-13 * m1, "{m1} vs {booked}");
}

/// A uniform air stream at Mach 2.9 through the 1D bridge of
/// [`coupled`]: FDM (0, 0.3) m, MPM (0.29, 0.4) m, outflow at both ends.
fn supersonic_stream() -> Cfdmp<IdealGas> {
    let u = 1000.0;
    let uniform = |_: [f64; 3]| PrimitiveState {
        density: RHO0,
        velocity: [u, 0.0, 0.0],
        pressure: P0,
    };
    let regions = BridgeRegions::from_boxes(
        RegionBox {
            lower: [0.0; 3],
            upper: [0.3, H, H],
        },
        RegionBox {
            lower: [0.29, 0.0, 0.0],
            upper: [0.4, H, H],
        },
        [H; 3],
        GHOST,
    )
    .unwrap();
    let (fg, _) = regions.fdm_grid(GHOST);
    let level = Level::new(fg.origin, fg.upper(), fg.cells, [1, 1, 1], GHOST).unwrap();
    let fdm = FdmSolver::new(
        IdealGas::air(),
        level,
        [FdmBoundary::Outflow; 6],
        FdmOptions::default(),
        uniform,
    )
    .unwrap();
    let (mg, _) = regions.mpm_grid();
    let level = Level::new(mg.origin, mg.upper(), mg.cells, [1, 1, 1], 0).unwrap();
    let air = IdealGas::air();
    let mut ps = Particles::new(0);
    let v = H * H * H / 2.0;
    for k in 0..110 {
        let x = 0.29 + (k as f64 + 0.5) * 0.5 * H;
        ps.push(
            &ParticleInit {
                position: [x, 0.5 * H, 0.5 * H],
                velocity: [u, 0.0, 0.0],
                mass: RHO0 * v,
                volume: v,
                stress: [-P0, -P0, -P0, 0.0, 0.0, 0.0],
                specific_internal_energy: air.specific_internal_energy(RHO0, P0).unwrap(),
                ..Default::default()
            },
            &[],
        )
        .unwrap();
    }
    let mut boundaries = [GridBoundary::Free; 6];
    boundaries[0] = GridBoundary::Outflow;
    boundaries[1] = GridBoundary::Outflow;
    let mpm = MpmSolver::new(
        level,
        vec![MaterialModel::Null(NullMaterial::air())],
        ps,
        MpmOptions {
            boundaries,
            bulk_viscosity: Some(BulkViscosity::default()),
            ..Default::default()
        },
    )
    .unwrap();
    Cfdmp::new(
        regions,
        fdm,
        mpm,
        GHOST,
        CfdmpOptions {
            air: MaterialId(0),
            products: None,
            gamma: air.gamma,
            existing_mass: RHO0 * v,
            // Below the stream's pressure: the MPM runs from step 1.
            activation_pressure: 0.5 * P0,
            activation_cells: 3,
            min_particle_mass: 0.25,
            existing_volume: 0.0,
            deposit: false,
            donor_rings: 1,
            start_in_bridge: None,
        },
    )
    .unwrap()
}

#[test]
fn a_supersonic_stream_leaves_the_fdm_region_exactly_uniform() {
    // Nothing travels upstream in a Mach 2.9 stream, so the fictitious
    // cells take the FDM's own outflow state rather than the MPM's
    // (which differs from the stream by the MPM's discretisation): the
    // FDM region keeps the uniform state to the last bit.
    let mut c = supersonic_stream();
    let want = c.fdm().cell_conservative([10, 0, 0]).unwrap();
    for _ in 0..60 {
        let dt = c.stable_dt().unwrap();
        c.advance(dt).unwrap();
    }
    assert!(c.is_active());
    let lines = c.transport_totals().supersonic_outflow;
    assert_eq!(lines, 59, "one line per active step");
    let n = c.regions().fdm.cells[0];
    for i in 0..n {
        let got = c.fdm().cell_conservative([i + c.fdm_offset, 0, 0]).unwrap();
        assert_eq!(got, want, "FDM cell {i}");
    }
    // The MPM took in the stream: created particles carried f_m > 0.
    assert!(c.transport_totals().into_mpm.mass > 0.0);
}

#[test]
fn in_a_stream_the_fdm_gives_up_the_enthalpy_flux_the_transport_and_donors_carry() {
    // The uniform stream, step by step after activation: the FDM
    // cells the bridge owns lose exactly (E + p) u Δt A a step, the
    // transport's E u Δt A (eqs 43–48) plus the pressure work p u Δt A
    // that the donor cells, as particles of the MPM step (eqs 37–39),
    // are to do on the MPM. The work they do is measured from their
    // own energy change over the MPM step and reported in
    // docs/physics/couple/bridge.md ("What the totals count").
    let mut c = supersonic_stream();
    let (mut transported, mut pressure_work, mut fdm_change) = (0.0, 0.0, 0.0);
    let mut active_steps = 0;
    for _ in 0..401 {
        let dt = c.stable_dt().unwrap();
        if !c.is_active() {
            c.advance(dt).unwrap();
            continue;
        }
        let (f0, tt0) = (fdm_owned_totals(&c), c.transport_totals());
        c.mpm_step(dt).unwrap();
        let donor = &c.inits[0];
        pressure_work += -donor.stress[0] * donor.velocity[0] * dt * c.regions.face_area();
        c.update_fictitious_cells().unwrap();
        c.fdm.advance(dt).unwrap();
        c.set_fictitious_values().unwrap();
        c.transport(dt).unwrap();
        c.time += dt;
        c.steps += 1;
        let tt = c.transport_totals();
        transported += tt.into_mpm.energy - tt0.into_mpm.energy;
        assert_eq!(tt.into_fdm.energy, tt0.into_fdm.energy, "no absorption");
        fdm_change += fdm_owned_totals(&c).energy - f0.energy;
        active_steps += 1;
    }
    assert!(active_steps >= 400);
    let given = transported + pressure_work;
    assert!(
        (fdm_change + given).abs() <= 1e-12 * given,
        "the FDM lost {} against {given}",
        -fdm_change
    );
    assert!(pressure_work > 0.1 * transported);
}

#[test]
fn the_totals_balance_a_stream_through_both_regions() {
    // The stream enters the FDM region through its flow-out face at
    // x = 0 and leaves the MPM region at x = 0.4 m: the bridge's
    // totals book the first through the FDM's face outflow and the
    // second through the MPM's, so they hold to round-off in mass
    // while more than half the coupled tube's content passes through.
    let mut c = supersonic_stream();
    let dt = c.stable_dt().unwrap();
    c.advance(dt).unwrap();
    assert!(c.is_active());
    let t0 = Solver::conservation_totals(&c);
    let inflow0 = c.fdm().outflow_where(|f, _| f == 0);
    for _ in 0..400 {
        let dt = c.stable_dt().unwrap();
        c.advance(dt).unwrap();
    }
    let t1 = Solver::conservation_totals(&c);
    let inflow = -(c.fdm().outflow_where(|f, _| f == 0).mass - inflow0.mass);
    assert!(inflow > 0.5 * t0.mass, "{inflow} {}", t0.mass);
    assert!(
        (t1.mass - t0.mass).abs() <= 1e-13 * t0.mass,
        "{} → {}",
        t0.mass,
        t1.mass
    );
    // Energy is not held to round-off here: the pressure work across
    // the interface reaches the MPM through the fictitious cells and
    // nodes, not the transport, and the totals drift by −0.84 % over
    // these 400 steps (docs/physics/couple/bridge.md, "What the
    // totals count").
}

#[test]
fn restart_continues_bit_identically_and_outputs_cover_the_union() {
    let mut c = coupled();
    while !c.is_active() || c.steps() < 200 {
        let dt = Solver::stable_dt(&c).unwrap();
        Solver::advance(&mut c, dt).unwrap();
    }
    let saved = c.save_state().unwrap();
    let run = |c: &mut Cfdmp<IdealGas>| {
        for _ in 0..30 {
            let dt = Solver::stable_dt(c).unwrap();
            Solver::advance(c, dt).unwrap();
        }
        let f = ["pressure".to_string(), "density".to_string()];
        (
            c.cell_data(&f).unwrap(),
            c.conservation_totals(),
            c.transport_totals(),
        )
    };
    let first = run(&mut c);
    let steps_first = c.particle_counts().particle_steps;
    c.restore_state(&saved).unwrap();
    let second = run(&mut c);
    assert_eq!(first.0, second.0);
    assert_eq!(first.1, second.1);
    assert_eq!(first.2, second.2);
    // The particle-steps count (the run summary's throughput) goes on
    // from the checkpoint's, not from where the first run ended.
    assert_eq!(c.particle_counts().particle_steps, steps_first);
    // The union: 150 FDM + 55 MPM − 5 bridge cells; x = 0.35 m reads
    // the MPM, x = 0.1 m the FDM.
    let data = first.0;
    assert_eq!(data.geometry.cells, [200, 1, 1]);
    let mut mpm = Vec::new();
    c.mpm()
        .sample([0.351, 0.001, 0.001], &["pressure".to_string()], &mut mpm)
        .unwrap();
    assert_eq!(data.fields[0].1[175], mpm[0]);
    let mut fdm = Vec::new();
    c.fdm()
        .sample([0.101, 0.001, 0.001], &["pressure".to_string()], &mut fdm)
        .unwrap();
    assert_eq!(data.fields[0].1[50], fdm[0]);
    let e = c.cell_data(&["mass_density".to_string()]).unwrap_err();
    assert!(e.to_string().contains("unknown field"), "{e}");
}

#[test]
fn the_time_split_is_json_with_every_part_named() {
    let counts = ParticleCounts {
        particles: 7,
        particle_steps: 70,
        created: 4,
        deposited: 3,
        absorbed: 1,
    };
    assert_eq!(
        time_split_json((1.5, 0.25), 12, Some(3.0e-6), counts),
        "{\n  \"fdm_seconds\": 1.5,\n  \"mpm_seconds\": 0.25,\n  \"steps\": 12,\n  \"activated_at\": 3e-6,\n  \"particles\": 7,\n  \"particle_steps\": 70,\n  \"created\": 4,\n  \"deposited\": 3,\n  \"absorbed\": 1\n}\n"
    );
    let none = ParticleCounts::default();
    assert!(time_split_json((0.0, 0.0), 0, None, none).contains("\"activated_at\": null"));
    assert!(time_split_json((f64::NAN, 1.0), 0, None, none).contains("\"fdm_seconds\": null"));
}

#[test]
fn finish_writes_the_split_of_a_run() {
    let mut c = coupled();
    while !c.is_active() {
        let dt = Solver::stable_dt(&c).unwrap();
        Solver::advance(&mut c, dt).unwrap();
    }
    for _ in 0..3 {
        let dt = Solver::stable_dt(&c).unwrap();
        Solver::advance(&mut c, dt).unwrap();
    }
    let (fdm, mpm) = c.split_seconds();
    assert!(fdm > 0.0 && mpm > 0.0, "{fdm} {mpm}");
    // The run summary's split is the same pair, named.
    assert_eq!(Solver::wall_split(&c), vec![("fdm", fdm), ("mpm", mpm)]);
    let dir = std::env::temp_dir().join(format!("brisance_split_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    c.finish(&dir).unwrap();
    let text = std::fs::read_to_string(dir.join(TIME_SPLIT_FILE)).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(
        text,
        time_split_json((fdm, mpm), c.steps(), c.activated_at(), c.particle_counts())
    );
    assert!(
        text.contains(&format!("\"steps\": {}", c.steps())),
        "{text}"
    );
}

#[test]
fn inflow_batches_make_fewer_particles_of_at_least_half_m_e() {
    // Threshold 4 m_e: every batch holds at least 4 m_e, so its
    // s = 4⌈M/4m_e⌉ particles weigh M/s ≥ m_e/2 each.
    let m_e = RHO0 * H * H * H / 2.0;
    let run = |min: f64| {
        let mut c = coupled_with(min);
        let first = c.mpm().particles().len() as u32;
        while c.time() < 5.5e-4 {
            let dt = Solver::stable_dt(&c).unwrap();
            Solver::advance(&mut c, dt).unwrap();
        }
        let ps = c.mpm().particles();
        let ids = c.mpm().particle_ids();
        let lightest = (0..ps.len())
            .filter(|&p| ids[p] >= first)
            .map(|p| ps.mass[p])
            .fold(f64::INFINITY, f64::min);
        let in_transit: f64 = c.pending.iter().map(|q| q.mass).sum();
        assert_eq!(c.pending.len(), 1, "one face in the 1D tube");
        (c.transport_totals(), lightest, in_transit)
    };
    let (paper, paper_lightest, none) = run(0.0);
    let (batched, lightest, in_transit) = run(1.0);
    assert_eq!(none, 0.0);
    assert!(paper.created > 0 && batched.created > 0);
    assert!(
        batched.created < paper.created,
        "{} vs {}",
        batched.created,
        paper.created
    );
    assert!(lightest >= 0.5 * m_e, "{lightest} {m_e}");
    assert!(paper_lightest < 0.5 * m_e, "{paper_lightest} {m_e}");
    // What waits is less than one batch.
    assert!(in_transit < 4.0 * m_e, "{in_transit}");
}

#[test]
fn deposited_inflow_is_in_the_mpm_region_the_step_it_arrives() {
    // The deposit rule: after every step nothing is in transit, and the
    // MPM's mass, momentum and energy change by exactly what the
    // transport booked plus what the MPM step itself did; the mass,
    // which the MPM step keeps, to round-off.
    let mut c = coupled_inflow(0.25, true);
    let m0 = c.mpm().conservation_totals().mass;
    let first = c.mpm().particles().len() as u32;
    let mut steps_with_inflow = 0;
    while c.time() < 5.5e-4 {
        let dt = Solver::stable_dt(&c).unwrap();
        let before = c.transport_totals().into_mpm.mass;
        Solver::advance(&mut c, dt).unwrap();
        if c.transport_totals().into_mpm.mass > before {
            steps_with_inflow += 1;
        }
        assert!(c.pending.iter().all(|q| q.mass == 0.0), "{:?}", c.pending);
        let tt = c.transport_totals();
        let m1 = c.mpm().conservation_totals().mass;
        let booked = m0 + tt.into_mpm.mass - tt.into_fdm.mass;
        assert!((m1 - booked).abs() < 1e-13 * m1, "{m1} vs {booked}");
    }
    let tt = c.transport_totals();
    assert!(steps_with_inflow > 10, "{steps_with_inflow}");
    // Inflow went into existing particles far more often than into new
    // ones, and the new ones grew by the deposits that followed.
    assert!(tt.deposited > 0 && tt.created > 0, "{tt:?}");
    assert!(tt.deposited > tt.created, "{tt:?}");
    let (paper, _, _) = {
        let mut p = coupled_with(0.0);
        while p.time() < 5.5e-4 {
            let dt = Solver::stable_dt(&p).unwrap();
            Solver::advance(&mut p, dt).unwrap();
        }
        (p.transport_totals(), 0, 0)
    };
    assert!(
        tt.created < paper.created,
        "{} vs {}",
        tt.created,
        paper.created
    );
    let ps = c.mpm().particles();
    let ids = c.mpm().particle_ids();
    let m_e = RHO0 * H * H * H / 2.0;
    let heaviest = (0..ps.len())
        .filter(|&p| ids[p] >= first)
        .map(|p| ps.mass[p])
        .fold(0.0, f64::max);
    assert!(heaviest > m_e, "{heaviest} {m_e}");
}

/// The FDM region's own cells (fictitious cells excepted) as totals.
fn fdm_owned_totals(c: &Cfdmp<IdealGas>) -> ConservationTotals {
    let mut t = Solver::conservation_totals(c);
    let m = c.mpm().conservation_totals();
    book_parts(&mut t, -m.mass, m.momentum.map(|x| -x), -m.energy);
    for q in &c.pending {
        book_parts(&mut t, -q.mass, q.momentum.map(|x| -x), -q.energy);
    }
    t
}

/// The MPM region's particles without this step's donor cells.
fn mpm_totals_without_donors(c: &Cfdmp<IdealGas>) -> ConservationTotals {
    let mut t = c.mpm().conservation_totals();
    let ps = c.mpm().particles();
    let ids = c.mpm().particle_ids();
    for p in (0..ps.len()).filter(|&p| c.is_donor(ids[p])) {
        // A particle of mass −m takes its mass, momentum and energy out.
        book(
            &mut t,
            -ps.mass[p],
            ps.velocity[p],
            ps.specific_internal_energy[p],
        );
    }
    t
}

fn difference(a: ConservationTotals, b: ConservationTotals) -> [f64; 5] {
    [
        a.mass - b.mass,
        a.momentum[0] - b.momentum[0],
        a.momentum[1] - b.momentum[1],
        a.momentum[2] - b.momentum[2],
        a.energy - b.energy,
    ]
}

#[test]
fn the_transport_moves_mass_momentum_and_energy_between_the_frames_to_round_off() {
    // Step 14 alone, on the coupled tube through the shock's arrival,
    // with both inflow rules: the MPM region changes by exactly the
    // inflow it booked less the particles the FDM absorbed, the FDM
    // region by exactly what it absorbed, in mass, every momentum
    // component and energy (`Cfdmp::advance`'s sequence, written out so
    // that the totals can be taken just before the transport).
    for deposit in [false, true] {
        transport_balances(coupled_inflow(0.25, deposit), deposit, 1.2e-3);
    }
    // The same with cpGIMP in the MPM region.
    let cp = coupled_of(0.25, true, 1, ShapeFunction::CpGimp);
    transport_balances(cp, true, 1.2e-3);
}

/// The coupled tube along z of an (r, z) grid, r 0–6H (6 rings, the
/// axis and a slip wall at r = 6H): FDM z (0, 0.3) m, MPM (0.29, 0.4) m,
/// w = 5, the shock tube's state along z; ring particles, 2 × 2 per
/// cell, and donor cells as 2 rings each.
fn coupled_rz(deposit: bool) -> Cfdmp<IdealGas> {
    let regions = BridgeRegions::from_boxes(
        RegionBox {
            lower: [0.0; 3],
            upper: [6.0 * H, 0.3, H],
        },
        RegionBox {
            lower: [0.0, 0.29, 0.0],
            upper: [6.0 * H, 0.4, H],
        },
        [H; 3],
        GHOST,
    )
    .unwrap();
    let (fg, _) = regions.fdm_grid(GHOST);
    let along_z = |x: [f64; 3]| initial([x[1], 0.0, 0.0]);
    let level = Level::new(
        fg.origin,
        fg.upper(),
        fg.cells,
        [1, 1, 1],
        brisance_fdm::GHOST_RZ,
    )
    .unwrap();
    let mut bcs = [FdmBoundary::Outflow; 6];
    bcs[0] = FdmBoundary::Reflective;
    bcs[1] = FdmBoundary::Reflective;
    bcs[2] = FdmBoundary::Reflective;
    let fdm = FdmSolver::new(
        IdealGas::air(),
        level,
        bcs,
        FdmOptions {
            geometry: Geometry::Axisymmetric,
            ..Default::default()
        },
        along_z,
    )
    .unwrap();
    let (mg, _) = regions.mpm_grid();
    let level = Level::new(mg.origin, mg.upper(), mg.cells, [1, 1, 1], 0).unwrap();
    let air = IdealGas::air();
    let mut ps = Particles::new(0);
    let ppc = 2;
    let first = regions.mpm.origin[1];
    let cells = ((regions.mpm.upper()[1] - first) / H).round() as usize;
    let mut per_radius = (0.0, 0);
    for c in 0..cells * ppc {
        for i in 0..6 * ppc {
            let z = first + (c as f64 + 0.5) / ppc as f64 * H;
            let r = (i as f64 + 0.5) / ppc as f64 * H;
            let st = along_z([r, z, 0.0]);
            let (rho, p) = (st.density, st.pressure);
            let v = 2.0 * std::f64::consts::PI * r * H * H / (ppc * ppc) as f64;
            if rho == RHO0 {
                per_radius = (per_radius.0 + rho * v / r, per_radius.1 + 1);
            }
            ps.push(
                &ParticleInit {
                    position: [r, z, 0.5 * H],
                    mass: rho * v,
                    volume: v,
                    stress: [-p, -p, -p, 0.0, 0.0, 0.0],
                    specific_internal_energy: air.specific_internal_energy(rho, p).unwrap(),
                    ..Default::default()
                },
                &[],
            )
            .unwrap();
        }
    }
    let mpm = MpmSolver::new(
        level,
        vec![MaterialModel::Null(NullMaterial::air())],
        ps,
        MpmOptions {
            boundaries: [
                GridBoundary::Symmetry,
                GridBoundary::Symmetry,
                GridBoundary::Outflow,
                GridBoundary::Symmetry,
                GridBoundary::Free,
                GridBoundary::Free,
            ],
            bulk_viscosity: Some(BulkViscosity::default()),
            geometry: Geometry::Axisymmetric,
            ..Default::default()
        },
    )
    .unwrap();
    Cfdmp::new(
        regions,
        fdm,
        mpm,
        GHOST,
        CfdmpOptions {
            air: MaterialId(0),
            products: None,
            gamma: air.gamma,
            existing_mass: per_radius.0 / per_radius.1 as f64,
            activation_pressure: 1.05 * P0,
            activation_cells: 3,
            min_particle_mass: 0.25,
            existing_volume: 0.0,
            deposit,
            donor_rings: 2,
            start_in_bridge: None,
        },
    )
    .unwrap()
}

#[test]
fn on_rings_the_transport_moves_mass_axial_momentum_and_energy_to_round_off() {
    // The same check on an (r, z) grid: every volume and area of the
    // exchange a ring's (eqs 40–51 with 2πr), the totals the rings'.
    for deposit in [false, true] {
        transport_balances(coupled_rz(deposit), deposit, 1.2e-3);
    }
}

#[test]
fn on_rings_a_geometry_mismatch_is_refused() {
    let c = coupled_rz(false);
    let (regions, fdm, mpm) = (c.regions, c.fdm, c.mpm);
    let mut options = c.options;
    options.donor_rings = 1;
    let cartesian_fdm = fdm_on(
        fdm.level().geometry.origin,
        fdm.level().geometry.upper(),
        fdm.level().geometry.cells,
        FdmBoundary::Outflow,
    );
    let e = Cfdmp::new(regions, cartesian_fdm, mpm, GHOST, options).unwrap_err();
    assert!(e.contains("one geometry"), "{e}");
}

/// Runs `c` to `end` with step 14 checked against its bookings (the
/// body of the transport tests).
fn transport_balances(mut c: Cfdmp<IdealGas>, deposit: bool, end: f64) {
    {
        let (mut transports, mut moved) = (0, [0u64; 2]);
        let mut worst = 0.0f64;
        while c.time() < end {
            let dt = c.stable_dt().unwrap();
            if !c.is_active() {
                c.advance(dt).unwrap();
                continue;
            }
            c.mpm_step(dt).unwrap();
            c.update_fictitious_cells().unwrap();
            c.fdm.advance(dt).unwrap();
            c.set_fictitious_values().unwrap();
            let (mpm0, fdm0, tt0) = (
                mpm_totals_without_donors(&c),
                fdm_owned_totals(&c),
                c.transport_totals(),
            );
            c.transport(dt).unwrap();
            c.time += dt;
            c.steps += 1;
            let tt = c.transport_totals();
            let into_mpm = difference(tt.into_mpm, tt0.into_mpm);
            let into_fdm = difference(tt.into_fdm, tt0.into_fdm);
            let d_mpm = difference(c.mpm().conservation_totals(), mpm0);
            let d_fdm = difference(fdm_owned_totals(&c), fdm0);
            // Scales: the region's own totals (momentum by the mass
            // times the largest speed in the tube, 500 m/s).
            let m = mpm0.mass.max(fdm0.mass);
            let scale = [
                m,
                500.0 * m,
                500.0 * m,
                500.0 * m,
                mpm0.energy.max(fdm0.energy),
            ];
            for k in 0..5 {
                let tol = 1e-13 * scale[k];
                let expected = into_mpm[k] - into_fdm[k];
                worst = worst
                    .max((d_mpm[k] - expected).abs() / scale[k])
                    .max((d_fdm[k] - into_fdm[k]).abs() / scale[k]);
                assert!(
                    (d_mpm[k] - expected).abs() <= tol,
                    "deposit {deposit}, t {}: MPM component {k} changed by {} against {expected} booked",
                    c.time,
                    d_mpm[k]
                );
                assert!(
                    (d_fdm[k] - into_fdm[k]).abs() <= tol,
                    "deposit {deposit}, t {}: FDM component {k} changed by {} against {} absorbed",
                    c.time,
                    d_fdm[k],
                    into_fdm[k]
                );
            }
            transports += 1;
            moved[0] += u64::from(into_mpm[0] > 0.0);
            moved[1] += u64::from(into_fdm[0] > 0.0);
        }
        // The check saw traffic both ways.
        eprintln!(
            "deposit {deposit}: {transports} transports, inflow in {}, absorption in {}, largest imbalance {worst:e} of the scale",
            moved[0], moved[1]
        );
        assert!(transports > 50, "{transports}");
        assert!(
            moved[0] > 10 && moved[1] > 0,
            "deposit {deposit}: {moved:?}"
        );
    }
}

#[test]
fn the_mpm_region_starts_the_step_the_shock_reaches_the_watched_cells() {
    // Before activation the coupled FDM is the tube's FDM (its
    // fictitious cells held at the undisturbed state the shock has not
    // reached): a pure FDM tube stepped with the same steps reads the
    // pressure of the watched cells (the donor cell and the two before
    // it) independently. The MPM region must start at the end of the
    // first step where one of them reaches 1.05 P0, and not before;
    // until then its particles do not move.
    let mut c = coupled();
    let mut reference = fdm_on([0.0; 3], [0.4, H, H], [200, 1, 1], FdmBoundary::Reflective);
    let positions = c.mpm().particles().position.clone();
    let donor_x =
        c.fdm()
            .level()
            .geometry
            .cell_centre([c.fdm_index(c.regions().donor_cell()), 0, 0])[0];
    let watched: Vec<f64> = (0..3).map(|k| donor_x - k as f64 * H).collect();
    let mut steps = 0;
    loop {
        assert!(!c.is_active());
        assert_eq!(c.activated_at(), None);
        let dt = c.stable_dt().unwrap();
        c.advance(dt).unwrap();
        reference.advance(dt).unwrap();
        steps += 1;
        let reached = watched
            .iter()
            .any(|&x| sample(&reference, x) >= c.options.activation_pressure);
        assert_eq!(c.is_active(), reached, "step {steps}, t {}", c.time());
        if reached {
            assert_eq!(c.activated_at(), Some(c.time()));
            break;
        }
        assert_eq!(c.mpm().particles().position, positions);
        assert_eq!(c.mpm().time(), 0.0);
        assert!(steps < 10_000);
    }
    // The shock of the 5:1 tube (about 530 m/s) runs the 0.184 m from
    // the diaphragm to the first watched cell in about 350 µs.
    let t = c.activated_at().unwrap();
    assert!((2.5e-4..4.5e-4).contains(&t), "{t}");
    // After it, the step is the smaller of the two CFL limits.
    let f = c.fdm().stable_dt().unwrap();
    let m = c.mpm().stable_dt().unwrap();
    assert_eq!(c.stable_dt().unwrap(), f.min(m));
    assert!(m != f);
}

/// The shock tube of [`coupled`] on 2 and 3 ranks of threads
/// ([`Cfdmp::distribute`]), through activation and the inflow of new
/// particles to 0.6 ms: every rank holds the state of one rank, bit for
/// bit, and each received at least the 21 values a particle a step of the
/// others' particle updates (Σ over the MPM steps of n − ⌈n/ranks⌉), so
/// the update was split.
#[test]
fn the_bridge_on_thread_ranks_gives_the_bits_of_one() {
    let t_end = 6.0e-4;
    let run = |ranks: usize| {
        crate::thread_ranks::on_thread_ranks(ranks, |comm| {
            let mut c = coupled();
            c.distribute(comm);
            let mut mpm_steps = 0u64;
            while c.time() < t_end {
                mpm_steps += u64::from(c.is_active());
                let dt = c.stable_dt().unwrap().min(t_end - c.time());
                c.advance(dt).unwrap();
            }
            let counts = c.particle_counts();
            assert!(counts.created > 0, "{counts:?}");
            (c.save_state().unwrap(), counts.particle_steps, mpm_steps)
        })
    };
    let ((one, particle_steps, mpm_steps), none) = run(1).remove(0);
    assert_eq!(none, 0);
    assert!(mpm_steps > 0);
    for ranks in [2u64, 3] {
        for (r, ((state, _, _), received)) in run(ranks as usize).into_iter().enumerate() {
            assert!(state == one, "rank {r} of {ranks}: the state differs");
            let bound = 21 * (particle_steps - particle_steps / ranks - mpm_steps);
            assert!(
                received >= bound,
                "rank {r} of {ranks} received {received} values, fewer than {bound}"
            );
        }
    }
}

/// `start_in_bridge: Some(2)` on the 1D tube: the MPM region starts later
/// than seed 001's rule (the shock 2 cells into the bridge instead of 3
/// cells before the interface); joining gives every air particle of the
/// bridge its FDM cell's density and velocity and leaves the rest alone;
/// the change is booked as inflow, so the MPM's mass stays the booked
/// inflow less the absorbed mass to round-off through the run.
#[test]
fn rows_started_inside_the_bridge_take_the_fdm_state_and_book_it() {
    let activation = |start: Option<usize>| {
        let mut c = coupled();
        c.options.start_in_bridge = start;
        c.joined = vec![start.is_none(); c.faces.len()];
        while !c.is_active() {
            let dt = c.stable_dt().unwrap();
            c.advance(dt).unwrap();
        }
        c
    };
    let seed = activation(None);
    let mut c = activation(Some(2));
    assert!(c.time() > seed.time(), "{} vs {}", c.time(), seed.time());
    assert!(!c.joined[0]);
    let m0 = c.mpm().conservation_totals().mass;
    let before: Vec<_> = {
        let ps = c.mpm().particles();
        (0..ps.len())
            .map(|p| (ps.position[p], ps.mass[p]))
            .collect()
    };
    c.join_rows().unwrap();
    assert!(c.joined[0]);
    let (fg, a) = (c.fdm().level().geometry, c.regions.axis);
    let first = c.fdm_index(c.regions.first_bridge_cell());
    let bridge = first..first + c.regions.width;
    let ps = c.mpm().particles();
    let mut restarted = 0;
    for p in 0..ps.len() {
        let cell = fg.cell_containing(ps.position[p]);
        if let Some(cell) = cell.filter(|q| bridge.contains(&q[a])) {
            let (s, _) = c.primitive(cell);
            let rho = ps.mass[p] / ps.volume[p];
            assert!(
                (rho - s.density).abs() <= 1e-12 * s.density,
                "{rho} vs {}",
                s.density
            );
            assert_eq!(ps.velocity[p], s.velocity);
            restarted += 1;
        } else {
            assert!(before.contains(&(ps.position[p], ps.mass[p])));
        }
    }
    // The shock is inside the bridge: the particles there move.
    assert!(ps.velocity.iter().any(|v| v[0] > 10.0));
    assert_eq!(c.transport_totals().restarted, restarted);
    assert_eq!(restarted, 2 * c.regions.width as u64);
    let booked = c.transport_totals().into_mpm.mass;
    let m1 = c.mpm().conservation_totals().mass;
    assert!((m1 - m0 - booked).abs() < 1e-13 * m1, "{m1} {m0} {booked}");
    while c.time() < 6.0e-4 {
        let dt = c.stable_dt().unwrap();
        c.advance(dt).unwrap();
    }
    let t = c.transport_totals();
    let m = c.mpm().conservation_totals().mass;
    let drift = m - m0 - t.into_mpm.mass + t.into_fdm.mass;
    assert!(drift.abs() < 1e-13 * m, "{drift:e} of {m:e} kg");
    assert_eq!(t.restarted, restarted, "one row joins once");
}

/// With `start_in_bridge`, a checkpoint written before the row joins (the
/// step the MPM region starts) and one written after both continue in a
/// fresh solver bit-identically: whether the row has joined is saved.
#[test]
fn a_restart_around_the_rows_joining_continues_bit_identically() {
    let started = || {
        let mut c = coupled();
        c.options.start_in_bridge = Some(2);
        c.joined = vec![false; c.faces.len()];
        c
    };
    let run = |c: &mut Cfdmp<IdealGas>| {
        for _ in 0..30 {
            let dt = Solver::stable_dt(c).unwrap();
            Solver::advance(c, dt).unwrap();
        }
        let f = ["pressure".to_string(), "density".to_string()];
        (c.cell_data(&f).unwrap(), c.transport_totals())
    };
    for extra in [0, 5] {
        let mut c = started();
        while !c.is_active() {
            let dt = Solver::stable_dt(&c).unwrap();
            Solver::advance(&mut c, dt).unwrap();
        }
        for _ in 0..extra {
            let dt = Solver::stable_dt(&c).unwrap();
            Solver::advance(&mut c, dt).unwrap();
        }
        assert_eq!(c.joined[0], extra > 0);
        let saved = c.save_state().unwrap();
        let first = run(&mut c);
        let mut fresh = started();
        fresh.restore_state(&saved).unwrap();
        let second = run(&mut fresh);
        assert_eq!(first.0, second.0);
        assert_eq!(first.1, second.1);
        assert!(first.1.restarted > 0);
    }
}
