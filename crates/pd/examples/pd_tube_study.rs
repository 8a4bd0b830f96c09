//! A tube study around `brisance_pd::cases` (the E-PD-CYL definition):
//! runs a copper tube of a given length and spacing to a given time with
//! chosen short-range force parameters, and prints the mid-length wall
//! velocity, the energy budget and the products nodes outside the case.
//!
//! `cargo run --release -p brisance-pd --example pd_tube_study -- \
//!    LENGTH_M END_S SPACING_M [DISTANCE_FACTOR REFERENCE_FRACTION FORCE_FACTOR]`
//!
//! Environment: `VISC=α,β[,α_s[,α_d]]` turns on the products' artificial viscosity
//! (α_s: the linear term on receding pairs too, `GasViscosity::shear`);
//! `PUSH=1` applies the products' force to explosive not yet detonated
//! (it matters only for an explosive without a `reactant`; the cases' TNT
//! has one, so its unreacted nodes are a Murnaghan solid and never held);
//! `PCONTACT=1` turns on eq 27 between the nodes of the charge
//! (`PdSolver::set_products_contact`); `LINE=1` lights the charge along its axis at t = 0 (radial flow only);
//! `STEEL=1` runs the steel tube of E-PD-FRAG; `DSCALE=k` runs the
//! program burn's front at k times the CJ detonation velocity (the
//! products unchanged); `HEAVY=k` multiplies the case's density by k (a
//! nearly rigid tube for k ≫ 1); `EVERY=s` sets the print
//! interval; `JUMP=f` prints each step in which the booked total changes
//! by more than f of the initial, with the nodes that gained most kinetic
//! energy in it. The "viscous heat" column is `PdSolver::viscous_heat`, which
//! also counts the reactant's compression energy handed to the products at
//! detonation. The products' kinetic energy is split into axial,
//! transverse, about the family mean and non-affine parts
//! (`cases::ProductsMotion`); the case's kinetic energy along the tube
//! and its axial momentum follow them, then the mass-weighted mean axial
//! velocity of the products now in the middle fifth of the
//! tube. `PROFILE=1` adds the products' axial kinetic energy and momentum
//! along the tube (`axial_profile`), `SHELLS=1` their motion in shells of
//! reference radius at mid-length (`shells`). `FAMILY=WithSolids` or
//! `FAMILY=MirroredWall` sets the products' families
//! (`ProductsFamily`). `LAYERS=1` adds, at
//! each print, the case's mean radial velocity at mid-length in layers of
//! reference radius one spacing thick (inner to outer) and the mean
//! pressure and radial velocity of the products within a spacing of the
//! case there (`layers`), after a first line with the detonation time of
//! the axis node nearest mid-length.

use brisance_core::Solver;
use brisance_pd::cases::{
    copper_cylinder, middle_of, products_through_case, steel_fragmenting_cylinder, EnergyBudget,
    ProductsMotion,
};
use brisance_pd::{ContactOptions, GasViscosity, PdSolver};

fn main() -> Result<(), String> {
    let a: Vec<f64> = std::env::args()
        .skip(1)
        .map(|s| s.parse::<f64>().map_err(|e| format!("argument `{s}`: {e}")))
        .collect::<Result<_, _>>()?;
    let get = |i: usize, d: f64| a.get(i).copied().unwrap_or(d);
    let (length, end, h) = (get(0, 0.06), get(1, 16.0e-6), get(2, 1.3e-3));
    let d = ContactOptions::default();
    let contact = ContactOptions {
        distance_factor: get(3, d.distance_factor),
        reference_fraction: get(4, d.reference_fraction),
        force_factor: get(5, d.force_factor),
    };
    let mut case = if std::env::var_os("STEEL").is_some() {
        steel_fragmenting_cylinder(h, length, 0.0, 0.0)
    } else {
        copper_cylinder(h, length)
    };
    // HEAVY=k: the case's density times k (its sound speed unchanged, so
    // its modulus times k too): k ≫ 1 holds the products in a nearly
    // rigid tube.
    if let Some(k) = std::env::var("HEAVY")
        .ok()
        .and_then(|v| v.parse::<f64>().ok())
    {
        case.metal.density *= k;
    }
    let mut setup = case.setup().map_err(|e| e.to_string())?;
    setup.options.contact = Some(contact);
    // FAMILY=WithSolids|MirroredWall: the products' families
    // (`ProductsFamily`; the printed `OwnBody` by default).
    match std::env::var("FAMILY").as_deref() {
        Ok("WithSolids") => setup.options.products_family = brisance_pd::ProductsFamily::WithSolids,
        Ok("MirroredWall") => {
            setup.options.products_family = brisance_pd::ProductsFamily::MirroredWall
        }
        Ok("OwnBody") | Err(_) => {}
        Ok(other) => {
            return Err(format!(
                "FAMILY `{other}`: OwnBody, WithSolids or MirroredWall"
            ))
        }
    }
    // DSCALE=k: the program burn's front runs at k times the CJ detonation
    // velocity (the products' isentrope unchanged).
    if let Some(k) = std::env::var("DSCALE")
        .ok()
        .and_then(|v| v.parse::<f64>().ok())
    {
        for m in &mut setup.materials {
            if let brisance_pd::PdMaterial::Gas(g) = m {
                g.detonation_velocity *= k;
            }
        }
    }
    // LINE=1: the charge lit along its whole axis at t = 0 (straight-line
    // burn from points one spacing apart): the products expand radially,
    // with no axial flow away from the ends.
    if std::env::var_os("LINE").is_some() {
        if let Some(d) = setup.detonation.as_mut() {
            let n = (length / h).ceil() as usize;
            d.points = (0..=n)
                .map(|k| brisance_pd::DetonationPoint {
                    position: [0.0, 0.0, (k as f64 * h).min(length)],
                    time: 0.0,
                })
                .collect();
            d.method = brisance_pd::BurnMethod::StraightLine;
        }
    }
    let t0 = std::time::Instant::now();
    let mut s = PdSolver::new(setup).map_err(|e| e.to_string())?;
    // PUSH=1: the products push unreacted explosive (eq 19 as printed).
    if std::env::var_os("PUSH").is_some() {
        s.set_hold_unreacted(false);
    }
    // PCONTACT=1: eq 27 between the nodes of the charge too.
    if std::env::var_os("PCONTACT").is_some() {
        s.set_products_contact(true);
    }
    // VISC=α,β[,α_s[,α_d]]: with the products' artificial viscosity (off by
    // default); α_s the linear term on receding pairs too, α_d the
    // deviatoric term.
    if let Ok(v) = std::env::var("VISC") {
        let c: Vec<f64> = v.split(',').filter_map(|x| x.parse().ok()).collect();
        s.set_gas_viscosity(Some(GasViscosity {
            linear: c.first().copied().unwrap_or(1.0),
            quadratic: c.get(1).copied().unwrap_or(2.0),
            shear: c.get(2).copied().unwrap_or(0.0),
            deviatoric: c.get(3).copied().unwrap_or(0.0),
        }))
        .map_err(|e| e.to_string())?;
    }
    let ring: Vec<usize> = (0..s.node_count())
        .filter(|&i| {
            let x = s.reference()[i];
            s.materials()[i] == 0
                && (x[2] - 0.5 * length).abs() <= h
                && x[0].hypot(x[1]) > case.outer_radius - h
        })
        .collect();
    let e0 = EnergyBudget::of(&s).total();
    let mid = |s: &PdSolver| {
        let mut v = 0.0;
        for &i in &ring {
            let y = s.current_position(i);
            let r = y[0].hypot(y[1]);
            let w = s.velocities()[i];
            v += (w[0] * y[0] + w[1] * y[1]) / r;
        }
        v / ring.len() as f64
    };
    let mut steps = 0u64;
    let every: f64 = std::env::var("EVERY")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(2.0e-6);
    let mut next = every;
    // JUMP=f: print every step whose booked total changes by more than the
    // fraction f of the initial, with the nodes whose kinetic energy grew
    // most in it.
    let jump: Option<f64> = std::env::var("JUMP").ok().and_then(|v| v.parse().ok());
    let kinetic = |s: &PdSolver| -> Vec<f64> {
        (0..s.node_count())
            .map(|i| {
                let v = s.velocities()[i];
                0.5 * s.mass(i) * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
            })
            .collect()
    };
    // The booked total after the last step (the next step's "before").
    let mut total = e0;
    let layered = std::env::var_os("LAYERS").is_some();
    if layered {
        let axis = (0..s.node_count())
            .filter(|&i| s.materials()[i] != 0)
            .min_by(|&a, &b| {
                let d = |i: usize| {
                    let x = s.reference()[i];
                    x[0].hypot(x[1]) + (x[2] - 0.5 * length).abs()
                };
                d(a).total_cmp(&d(b))
            });
        if let Some(i) = axis {
            println!(
                "front at mid-length on the axis: {:.3} us (node at r {:.2} mm z {:.2} mm)",
                s.detonation_times()[i] * 1e6,
                s.reference()[i][0].hypot(s.reference()[i][1]) * 1e3,
                s.reference()[i][2] * 1e3
            );
        }
    }
    while s.time() < end {
        let dt = s.stable_dt().map_err(|e| e.to_string())?;
        let before = jump.map(|_| (total, kinetic(&s)));
        s.advance(dt.min(end - s.time()).max(1e-15))
            .map_err(|e| e.to_string())?;
        if let (Some(f), Some((e_before, k_before))) = (jump, before) {
            let e_after = EnergyBudget::of(&s).total();
            total = e_after;
            if ((e_after - e_before) / e0).abs() > f {
                let k_after = kinetic(&s);
                let mut gain: Vec<(f64, usize)> = (0..s.node_count())
                    .map(|i| (k_after[i] - k_before[i], i))
                    .collect();
                gain.sort_by(|a, b| b.0.total_cmp(&a.0));
                println!(
                    "jump at step {} t {:.4} us dt {:.3e}: total {:+.4e} of E0 ({:+.1} J); limit {:?}",
                    steps + 1,
                    s.time() * 1e6,
                    dt,
                    (e_after - e_before) / e0,
                    e_after - e_before,
                    s.limiting_node()
                );
                for &(g, i) in gain.iter().take(6) {
                    let x = s.current_position(i);
                    let x0 = s.reference()[i];
                    println!(
                        "  node {i} material {} KE +{:.1} J (now {:.1} J), at r {:.2} mm z {:.2} mm (from r {:.2} z {:.2}), X {:.3}, p {:.3e} Pa, damage {:.3}",
                        s.materials()[i],
                        g,
                        k_after[i],
                        x[0].hypot(x[1]) * 1e3,
                        x[2] * 1e3,
                        x0[0].hypot(x0[1]) * 1e3,
                        x0[2] * 1e3,
                        s.expansion(i),
                        s.pressure(i),
                        s.damage(i)
                    );
                }
            }
        }
        steps += 1;
        if s.time() >= next || s.time() >= end {
            next += every;
            let e = EnergyBudget::of(&s);
            let released = e0 - e.products;
            let motion = ProductsMotion::of(&s);
            let (disorder, nonaffine) = (motion.about_family_mean, motion.non_affine);
            let (axial, transverse) = (motion.axial, motion.transverse);
            let (pz_products, pz) = (motion.products_momentum_z, motion.total_momentum_z);
            let (through, counted) = products_through_case(&s, h, middle_of(length));
            let (mut case_axial, mut case_pz) = (0.0, 0.0);
            for i in 0..s.node_count() {
                if s.materials()[i] == 0 {
                    let vz = s.velocities()[i][2];
                    case_axial += 0.5 * s.mass(i) * vz * vz;
                    case_pz += s.mass(i) * vz;
                }
            }
            let slab_vz = middle_fifth_axial_velocity(&s, length);
            println!(
                "t {:5.1} us  steps {steps:5}  dt {:.2e}  mid v {:7.1} m/s  E/E0 {:.4}  case KE {:5.1} % prod KE {:5.1} % bonds {:4.1} % contacts {:.2} % dissipated {:.2} % of released {:.1} kJ  through {through}/{counted}  disordered {:.1} % (non-affine {:.1} %)  viscous heat {:.1} %  prod KE axial {:.1} % transverse {:.1} %  p_z products {:.2} total {:.2} N s  case KE axial {:.1} % p_z {:.2} N s  mid-fifth products v_z {:.0} m/s",
                s.time() * 1e6,
                dt,
                mid(&s),
                e.total() / e0,
                100.0 * e.case_kinetic / released,
                100.0 * e.products_kinetic / released,
                100.0 * e.bonds / released,
                100.0 * e.contact / released,
                100.0 * e.dissipated / released,
                released * 1e-3,
                100.0 * disorder / released,
                100.0 * nonaffine / released,
                100.0 * s.viscous_heat() / released,
                100.0 * axial / released,
                100.0 * transverse / released,
                pz_products,
                pz,
                100.0 * case_axial / released,
                case_pz,
                slab_vz,
            );
            if std::env::var_os("PROFILE").is_some() {
                axial_profile(&s, case.inner_radius, length, released);
            }
            if std::env::var_os("SHELLS").is_some() {
                shells(&s, case.inner_radius, h, length);
            }
            if layered {
                layers(&s, case.inner_radius, h, length);
            }
        }
    }
    let f = s.fragments();
    let case_nodes: Vec<usize> = (0..s.node_count())
        .filter(|&i| s.materials()[i] == 0)
        .collect();
    let dmax = case_nodes.iter().map(|&i| s.damage(i)).fold(0.0, f64::max);
    let dmean = case_nodes.iter().map(|&i| s.damage(i)).sum::<f64>() / case_nodes.len() as f64;
    println!(
        "fragments {} largest {:.4e} kg  case damage mean {dmean:.3} max {dmax:.3}",
        f.len(),
        f.first().map_or(0.0, |f| f.mass)
    );
    // The same open-cylinder relation with the energy the model's own
    // products give from X = 1 to X = 7 (the volume-burn isentrope).
    let products = brisance_pd::cases::tnt_products().map_err(|e| e.to_string())?;
    let w = (products.isentrope.energy(1.0) - products.isentrope.energy(7.0)) / products.density;
    let own = brisance_eos::tools::cylinder_wall_velocity((2.0 * w).sqrt(), case.metal_to_charge())
        .map_err(|e| e.to_string())?;
    println!(
        "nodes {} Gurney {:.1} m/s (volume-burn isentrope X 1 to 7: {own:.1} m/s) wall {:.1} s",
        s.node_count(),
        case.gurney_wall_velocity()?,
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}

/// The mass-weighted mean axial velocity of the products now in the
/// middle fifth of the tube (current z).
fn middle_fifth_axial_velocity(s: &PdSolver, length: f64) -> f64 {
    let (mut m, mut mv) = (0.0, 0.0);
    for i in 0..s.node_count() {
        let z = s.current_position(i)[2];
        if s.materials()[i] != 0 && (z - 0.5 * length).abs() <= 0.1 * length {
            m += s.mass(i);
            mv += s.mass(i) * s.velocities()[i][2];
        }
    }
    if m > 0.0 {
        mv / m
    } else {
        0.0
    }
}

/// `PROFILE=1`: the products' axial kinetic energy (share of the released
/// energy) and axial momentum in six bins of current z along the tube
/// (nodes beyond the ends in the end bins), then the mean v_z in twelve
/// bins of current z by four bins of reference radius (quarters of the
/// case's inner radius) and the share of the axial kinetic energy those bin
/// means carry.
fn axial_profile(s: &PdSolver, inner_radius: f64, length: f64, released: f64) {
    let (mut ke, mut pz) = ([0.0f64; 6], [0.0f64; 6]);
    let (mut m, mut mv) = ([[0.0f64; 4]; 12], [[0.0f64; 4]; 12]);
    for i in 0..s.node_count() {
        if s.materials()[i] == 0 {
            continue;
        }
        let z = s.current_position(i)[2] / length;
        let vz = s.velocities()[i][2];
        let mi = s.mass(i);
        let b6 = ((z * 6.0).floor().max(0.0) as usize).min(5);
        ke[b6] += 0.5 * mi * vz * vz;
        pz[b6] += mi * vz;
        let b12 = ((z * 12.0).floor().max(0.0) as usize).min(11);
        let x0 = s.reference()[i];
        let rb = ((x0[0].hypot(x0[1]) / inner_radius * 4.0) as usize).min(3);
        m[b12][rb] += mi;
        mv[b12][rb] += mi * vz;
    }
    let ke: Vec<String> = ke
        .iter()
        .map(|k| format!("{:.1}", 100.0 * k / released))
        .collect();
    let pz: Vec<String> = pz.iter().map(|p| format!("{p:.1}")).collect();
    println!(
        "  products axial KE by sixth of the tube (% of released) {}  p_z (N s) {}",
        ke.join(" "),
        pz.join(" ")
    );
    let mut resolved = 0.0;
    for b in 0..12 {
        let row: Vec<String> = (0..4)
            .map(|rb| {
                if m[b][rb] > 0.0 {
                    resolved += 0.5 * mv[b][rb] * mv[b][rb] / m[b][rb];
                    format!("{:6.0}", mv[b][rb] / m[b][rb])
                } else {
                    "     -".into()
                }
            })
            .collect();
        println!("    z bin {b:2}: v_z by r0 quarter {}", row.join(" "));
    }
    println!(
        "  axial KE of the bin means {:.1} % of released",
        100.0 * resolved / released
    );
}

/// `SHELLS=1`: the products nodes of the middle twelfth of the tube
/// (reference z) in shells of reference radius one spacing wide: share of
/// the slab's products mass and kinetic energy (axial + radial), mean and
/// spread of v_z and of the radial velocity; then the outer two shells by
/// azimuth folded onto one quadrant of the lattice.
fn shells(s: &PdSolver, inner_radius: f64, h: f64, length: f64) {
    let nb = (inner_radius / h).ceil() as usize + 1;
    let mut acc = vec![[0.0f64; 5]; nb];
    // The outer two shells by azimuth folded onto one lattice quadrant
    // (θ mod 90°, nine bins of 10°): share of their mass, rms speed.
    let mut az = [[0.0f64; 2]; 9];
    for i in 0..s.node_count() {
        let x0 = s.reference()[i];
        if s.materials()[i] == 0 || (x0[2] - 0.5 * length).abs() >= length / 24.0 {
            continue;
        }
        let shell = (x0[0].hypot(x0[1]) / h) as usize;
        let b = shell.min(nb - 1);
        let y = s.current_position(i);
        let v = s.velocities()[i];
        let vr = (v[0] * y[0] + v[1] * y[1]) / y[0].hypot(y[1]).max(1e-12);
        let m = s.mass(i);
        let a = &mut acc[b];
        a[0] += m;
        a[1] += m * v[2];
        a[2] += m * v[2] * v[2];
        a[3] += m * vr;
        a[4] += m * vr * vr;
        if shell + 2 >= nb - 1 {
            let theta = x0[1].atan2(x0[0]).to_degrees().rem_euclid(90.0);
            let t = ((theta / 10.0) as usize).min(8);
            az[t][0] += m;
            az[t][1] += m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        }
    }
    let outer: f64 = az.iter().map(|a| a[0]).sum();
    let row: Vec<String> = az
        .iter()
        .map(|a| {
            if a[0] > 0.0 {
                format!("{:.0} % {:.0}", 100.0 * a[0] / outer, (a[1] / a[0]).sqrt())
            } else {
                "-".into()
            }
        })
        .collect();
    println!(
        "    outer two shells by θ mod 90° (10° bins: mass share, rms speed m/s): {}",
        row.join(" | ")
    );
    let (mass, ke) = acc
        .iter()
        .fold((0.0, 0.0), |(m, k), a| (m + a[0], k + 0.5 * (a[2] + a[4])));
    for (b, a) in acc.iter().enumerate() {
        if a[0] > 0.0 {
            let (vz, vr) = (a[1] / a[0], a[3] / a[0]);
            println!(
                "    shell r0 {:4.1}-{:4.1} mm: mass {:4.1} %  KE (axial + radial) {:4.1} %  v_z {vz:6.0} ± {:4.0}  v_r {vr:6.0} ± {:4.0} m/s",
                b as f64 * h * 1e3,
                (b + 1) as f64 * h * 1e3,
                100.0 * a[0] / mass,
                100.0 * 0.5 * (a[2] + a[4]) / ke,
                (a[2] / a[0] - vz * vz).max(0.0).sqrt(),
                (a[4] / a[0] - vr * vr).max(0.0).sqrt()
            );
        }
    }
}

/// `LAYERS=1`: at mid-length (reference z within a spacing), the case's
/// mean radial velocity in layers of reference radius one spacing thick
/// from the inner radius out, and the products within a spacing of the
/// inner radius: their count, mean pressure and mean radial velocity.
fn layers(s: &PdSolver, inner_radius: f64, h: f64, length: f64) {
    let mut case = [[0.0f64; 2]; 8];
    let (mut n, mut p, mut vr_sum) = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..s.node_count() {
        let x0 = s.reference()[i];
        if (x0[2] - 0.5 * length).abs() > h {
            continue;
        }
        let r0 = x0[0].hypot(x0[1]);
        let y = s.current_position(i);
        let v = s.velocities()[i];
        let vr = (v[0] * y[0] + v[1] * y[1]) / y[0].hypot(y[1]).max(1e-12);
        if s.materials()[i] == 0 {
            let l = (((r0 - inner_radius) / h).max(0.0) as usize).min(7);
            case[l][0] += 1.0;
            case[l][1] += vr;
        } else if r0 > inner_radius - h {
            n += 1.0;
            p += s.pressure(i);
            vr_sum += vr;
        }
    }
    let row: Vec<String> = case
        .iter()
        .filter(|c| c[0] > 0.0)
        .map(|c| format!("{:6.0} ({})", c[1] / c[0], c[0]))
        .collect();
    println!(
        "    case v_r by layer (inner to outer, m/s (nodes)): {}  products by the wall: {} nodes, p {:.3e} Pa, v_r {:.0} m/s",
        row.join(" "),
        n,
        p / n.max(1.0),
        vr_sum / n.max(1.0)
    );
}
