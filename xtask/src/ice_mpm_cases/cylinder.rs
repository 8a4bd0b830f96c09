//! E-CYLINDER: the reduced copper cylinder test of seed 000 §5.2
//! (configs/cylinder_icempm.ron), and its energy-audit diagnostic.

use std::fmt::Write as _;
use std::time::Instant;

use anyhow::{anyhow, Result};

use crate::Report;
use brisance::verification::cylinder::{
    cylinder_quarter_run, QuarterRun, QuarterSetup, TubeGurney, QUARTER_GAUGE_Z,
};

/// E-CYLINDER: configs/cylinder_icempm.ron (the seed 000 §5.2 copper
/// cylinder test, reduced), run by `brisance_validation::cylinder::
/// cylinder_quarter_run`: the mean radial velocity of the outer-wall
/// particles that start within 1 mm of z = QUARTER_GAUGE_Z, time-shifted to
/// the detonation's arrival there (products volume fraction on the axis
/// above 1/2), and its terminal value against the Gurney estimate.
pub fn e_cylinder(report: &mut Report, img: &std::path::Path) -> Result<()> {
    if let Ok(path) = std::env::var("BRISANCE_CYLINDER_AUDIT") {
        return cylinder_audit(&path);
    }
    println!("E-CYLINDER: copper cylinder test on the IceMpm pipeline (reduced)");
    let run = cylinder_quarter_run(&QuarterSetup::shipped()).map_err(|e| anyhow!("{e}"))?;
    let QuarterRun {
        extent,
        cells,
        particles,
        steps,
        gauge_z,
        arrival,
        slice_end,
        relative_volume_end: v_end,
        gurney_at_end,
        energy_start,
        ..
    } = run;
    let wall = run.wall_s;
    let cell_rate = (cells * steps) as f64 / wall;
    let particle_rate = (particles * steps) as f64 / wall;
    let TubeGurney {
        cj,
        estimate: g,
        m_over_c,
        wall: gurney,
        ..
    } = &run.gurney;
    let (m_over_c, gurney) = (*m_over_c, *gurney);
    let t0 = arrival.unwrap_or(f64::NAN);
    let detonation_velocity = run.detonation_velocity();
    let booked = |totals: &[(String, brisance::ice::KeptWarmTotals)]| {
        totals
            .iter()
            .map(|(name, k)| format!("{name} {} cell-steps, {:+.3e} J", k.firings, k.energy))
            .collect::<Vec<_>>()
            .join("; ")
    };
    let warm = booked(&run.kept_warm);
    let warm12 = booked(&run.kept_warm_advection);
    println!(
        "  cold-material rule (kept_warm): step 2 {warm}; step 12 {warm12}; initial total energy {energy_start:.4e} J"
    );
    let terminal = run.terminal();
    let failure = &run.failure;
    println!(
        "  {steps} steps in {wall:.0} s ({cell_rate:.3e} cell-updates/s, {particle_rate:.3e} particle-steps/s, {cells} cells, {particles} particles), arrival at z = {:.1} cm {t0:e} s, terminal {terminal:.0} m/s, Gurney {gurney:.0} m/s (at the V = {v_end:.2} reached: {gurney_at_end:?}), failure {failure:?}",
        gauge_z * 100.0
    );
    let times: Vec<f64> = run.record.iter().map(|r| r.0).collect();
    let speeds: Vec<f64> = run.record.iter().map(|r| r.1).collect();
    // Plot v_r against t − t_arrival.
    let shifted: Vec<f64> = times.iter().map(|t| (t - t0) * 1e6).collect();
    let png = img.join("e_cylinder.png");
    if arrival.is_some() {
        use crate::plot::{plot_panels, Panel, Series, SeriesStyle};
        let g = vec![gurney; shifted.len()];
        plot_panels(
            &png,
            &format!(
                "E-CYLINDER: outer wall at z = {:.1} cm (IceMpm, reduced)",
                gauge_z * 100.0
            ),
            "t − t_arrival [µs]",
            &[Panel {
                y_label: "radial velocity [m/s]",
                series: vec![
                    Series {
                        label: "IceMpm",
                        x: &shifted,
                        y: &speeds,
                        style: SeriesStyle::Line,
                    },
                    Series {
                        label: "Gurney estimate",
                        x: &shifted,
                        y: &g,
                        style: SeriesStyle::Line,
                    },
                ],
            }],
        )?;
    }
    let md = &mut report.md;
    let _ = writeln!(
        md,
        "## E-CYLINDER — copper cylinder test, IceMpm (seed 000 §5.2)\n"
    );
    let _ = writeln!(
        md,
        "configs/cylinder_icempm.ron: OFHC copper tube r 25.4–30.6 mm (ρ 8930, K 117 GPa, G 43.8 GPa, \
         σy 70 MPa) filled with QM-100 (JWL++), air outside, quarter symmetry, 6 mm booster of products \
         at 10 GPa against a closed end at z = 0. **Reduced:** {:.0} cm of tube at h = 2 mm in a {:.0} × {:.0} mm quarter \
         section (the seed: 35 cm at 0.5 mm; the wall is 2.6 cells thick here), gauge at z = {:.1} cm instead of 25 cm. \
         {steps} steps to {:.1} µs, {wall:.0} s wall (2 cores, shared): {cells} cells and {particles} particles, \
         {cell_rate:.3e} cell-updates/s, {particle_rate:.3e} particle-steps/s. At the end the wall at the gauge \
         had expanded to an inner radius of {:.1} mm, products relative volume V = {v_end:.2}{}.{}\n",
        extent[2] * 1e2,
        extent[0] * 1e3,
        extent[1] * 1e3,
        gauge_z * 100.0,
        run.time * 1e6,
        run.inner_radius_end * 1e3,
        gurney_at_end.map_or(String::new(), |v| format!(
            " (the Gurney estimate at that V, same M/C: {v:.0} m/s)"
        )),
        failure
            .as_ref()
            .map_or(String::new(), |f| format!(" **The run stopped:** {f}"))
    );
    let _ = writeln!(
        md,
        "Detonation arrival at the gauge (products θ > ½ on the axis): {}. Gurney: √(2E_G) = {:.0} m/s at \
         V = 7 on the QM-100 principal isentrope, M/C = {m_over_c:.2}, open-ended cylinder: {gurney:.0} m/s. \
         The LLNL shot K260-581 of seed 000 fig. 5 is not tabulated in the seed and no published QM-100 \
         cylinder velocity was found to compare with; only the Gurney estimate is used.\n",
        arrival.map_or("not reached".into(), |t| format!("{:.2} µs", t * 1e6)),
        g.gurney_velocity
    );
    let _ = writeln!(
        md,
        "Diagnostics (docs/physics/couple/ice_mpm_cylinder_audit.md): detonation velocity on the axis, \
         least squares over the arrivals at z = {:.0}–{:.0} cm, {:.0} m/s against D_CJ = {:.0} m/s of the QM-100 \
         products ({:+.1} %); the whole wall at the gauge (particles starting within h/2 of z = {:.1} cm) \
         ends at a kinetic-energy mean radial velocity of {slice_end:.0} m/s{}. Step 2's cold-material \
         rule and trace hold (`kept_warm`, in step 2 and carried through steps 8–11; \
         docs/physics/ice/steps.md) fired over the run: {warm}; step 12's: {warm12} \
         (initial total energy of the quarter model {energy_start:.4e} J).\n",
        run.fronts.first().map_or(f64::NAN, |f| f.0 * 100.0),
        run.fronts.last().map_or(f64::NAN, |f| f.0 * 100.0),
        detonation_velocity,
        cj.detonation_velocity,
        100.0 * (detonation_velocity / cj.detonation_velocity - 1.0),
        gauge_z * 100.0,
        gurney_at_end.map_or(String::new(), |v| format!(
            " ({:+.1} % from the Gurney estimate at the V reached)",
            100.0 * (slice_end / v - 1.0)
        )),
    );
    if arrival.is_some() {
        let _ = writeln!(md, "![E-CYLINDER wall velocity](img/e_cylinder.png)\n");
    }
    let _ = writeln!(md, "| check | measured | target | |\n|---|---:|---:|---|");
    let err = terminal / gurney - 1.0;
    report.target(
        "E-CYLINDER terminal wall velocity vs Gurney",
        if terminal.is_finite() {
            format!("{terminal:.0} m/s ({:+.1} %)", 100.0 * err)
        } else {
            "run stopped".into()
        },
        "±10 %",
        terminal.is_finite() && err.abs() <= 0.10,
    );
    let _ = writeln!(report.md);
    Ok(())
}

/// Diagnostic of E-CYLINDER (not part of the report): with
/// `BRISANCE_CYLINDER_AUDIT=<config.ron>` set, `cargo xtask validate --only
/// cylinder` runs that config instead and prints the energy audit over time
/// and the state of the gauge slice, then stops without writing the report.
/// `BRISANCE_CYLINDER_AUDIT_EVERY` (steps between lines, default 20) and
/// `BRISANCE_CYLINDER_AUDIT_Z` (slice position, m, default QUARTER_GAUGE_Z).
pub fn cylinder_audit(path: &str) -> Result<()> {
    use brisance::compose::build::build_section;
    use brisance::compose::load_str;
    use brisance::core::{Eos, Solver};
    use brisance::eos::tools::{cj_on_jwl_cterm_isentrope, principal_isentrope};
    use brisance::eos::{EosModel, JwlCTerm};

    let text = std::fs::read_to_string(path).map_err(|e| anyhow!("{path}: {e}"))?;
    let loaded = load_str(path, &text, &[]).map_err(|e| anyhow!("{path}: {e}"))?;
    let s = &loaded.scenario;
    let Some(section) = s.pipeline.section::<brisance::couple::IceMpmConfig>() else {
        return Err(anyhow!("{path} is not an IceMpm pipeline"));
    };
    let mut solver = build_section(section, s).map_err(|e| anyhow!("{e}"))?;
    let every: usize = std::env::var("BRISANCE_CYLINDER_AUDIT_EVERY")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20);
    let zg: f64 = std::env::var("BRISANCE_CYLINDER_AUDIT_Z")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(QUARTER_GAUGE_Z);
    let t_end: f64 = std::env::var("BRISANCE_CYLINDER_AUDIT_END")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(s.time.end);
    let profile = std::env::var("BRISANCE_CYLINDER_AUDIT_PROFILE").is_ok();
    let eos = |name: &str| -> Result<EosModel> {
        s.materials
            .get(name)
            .and_then(|m| m.eos())
            .cloned()
            .ok_or_else(|| anyhow!("no eos for {name}"))
    };
    let fluids = ["qm100", "products", "air"];
    let feos: Vec<EosModel> = fluids.iter().map(|n| eos(n)).collect::<Result<_>>()?;
    let products: JwlCTerm = match feos[1] {
        EosModel::JwlCTerm(j) => j,
        _ => return Err(anyhow!("products not JwlCTerm")),
    };
    let q = brisance::reaction::jwlpp::detonation_energy(
        &match feos[0] {
            EosModel::Murnaghan(m) => m,
            _ => return Err(anyhow!("qm100 not Murnaghan")),
        },
        &products,
    )
    .map_err(|e| anyhow!("{e}"))?;
    let cj = cj_on_jwl_cterm_isentrope(&products).map_err(|e| anyhow!("{e}"))?;
    // e_s(V) on the principal isentrope, V on a log grid.
    let vs: Vec<f64> = (0..400)
        .map(|i| cj.relative_volume * (60.0 / cj.relative_volume).powf(i as f64 / 399.0))
        .collect();
    let isen = principal_isentrope(&products, &cj, &vs, 1e-10).map_err(|e| anyhow!("{e}"))?;
    let e_s = |v: f64| -> f64 {
        let v = v.clamp(vs[0], vs[399]);
        let x = (v / vs[0]).ln() / (60.0 / vs[0]).ln() * 399.0;
        let i = (x.floor() as usize).min(398);
        let f = x - i as f64;
        isen[i].specific_internal_energy * (1.0 - f) + isen[i + 1].specific_internal_energy * f
    };
    let e0 = cj.unreacted.specific_internal_energy;
    println!(
        "audit: Q = {q:.6e} J/kg, e0 = {e0:.6e}, CJ D = {:.1} p = {:.4e} u = {:.1} V = {:.4}",
        cj.detonation_velocity, cj.pressure, cj.particle_velocity, cj.relative_volume
    );
    let g = s.domain.clone();
    let nc = g.cells;
    let hx: [f64; 3] = std::array::from_fn(|d| (g.upper[d] - g.lower[d]) / nc[d] as f64);
    let vol = hx[0] * hx[1] * hx[2];
    let names: Vec<String> = [
        "pressure",
        "velocity_x",
        "velocity_y",
        "velocity_z",
        "volume_fraction_1",
        "density_1",
        "temperature_1",
        "volume_fraction_2",
        "density_2",
        "temperature_2",
        "volume_fraction_3",
        "density_3",
        "temperature_3",
        "volume_fraction_4",
        "density_4",
    ]
    .iter()
    .map(|x| x.to_string())
    .collect();
    let rho0 = products.rho0;
    let (r_in, r_out) = (0.0254, 0.0306);
    let charge_per_len = rho0 * std::f64::consts::PI * r_in * r_in / 4.0;
    let copper_per_len = 8930.0 * std::f64::consts::PI * (r_out * r_out - r_in * r_in) / 4.0;
    // Net outflow of the fluids' energy through the outflow faces, summed
    // each step from the boundary cells (first order: cell values at the
    // face; inflow counts negative).
    let mut fluid_out = [0.0f64; 3]; // energy, of which products, mass
    let mut arrivals: Vec<(f64, Option<f64>, f64)> = (1..20)
        .map(|i| (i as f64 * 0.005, None, 0.0))
        .filter(|a| a.0 < g.upper[2])
        .collect();
    let e_start = solver.conservation_totals().energy;
    let chem0 = {
        let d = solver.cell_data(&names)?;
        d.field("density_1").unwrap().iter().sum::<f64>() * vol * q
    };
    println!("audit: E_total(0) = {e_start:.6e} J, chemical energy of the reactant {chem0:.6e} J, charge {charge_per_len:.4} kg/m, copper {copper_per_len:.4} kg/m (quarter)");
    println!("t_us,E_cu_kin,E_cu_kin_r,E_cu_int,E_cu_out,E_ice,E_rescaled,E_fluid_out,residual,m_qm,m_pr,m_air,E_pr_int,E_pr_kin,E_air_int0,E_air_kin,E_pr_excess,burnt_frac | slice: V_pr,p_wall,pr_mass/charge,cu_kin_r/len,pr_kin/len,pr_excess/len,EG(V)*C,(cu_kin+pr_kin)/EG*C,r_in_mm");
    let mut steps = 0usize;
    let start = Instant::now();
    let air_e0 = |rho: f64| feos[2].specific_internal_energy_from_temperature(rho, 300.0);
    loop {
        let done = solver.time() >= t_end * (1.0 - 1e-12);
        let d = solver.cell_data(&names)?;
        let f = |n: &str| d.field(n).unwrap();
        let (p, ux, uy, uz) = (
            f("pressure"),
            f("velocity_x"),
            f("velocity_y"),
            f("velocity_z"),
        );
        let th: Vec<&[f64]> = (1..=4)
            .map(|k| f(&format!("volume_fraction_{k}")))
            .collect();
        let rh: Vec<&[f64]> = (1..=4).map(|k| f(&format!("density_{k}"))).collect();
        let tt: Vec<&[f64]> = (1..=3).map(|k| f(&format!("temperature_{k}"))).collect();
        let idx = |i: usize, j: usize, k: usize| i + nc[0] * (j + nc[1] * k);
        // energy per unit volume of fluid r in cell c (internal, kinetic).
        let e_of = |r: usize, c: usize| -> (f64, f64) {
            let rho = rh[r][c];
            if !(rho > 0.0) || !(th[r][c] > 0.0) {
                return (0.0, 0.0);
            }
            let micro = rho / th[r][c];
            let e = feos[r].specific_internal_energy_from_temperature(micro, tt[r][c]);
            let u2 = ux[c] * ux[c] + uy[c] * uy[c] + uz[c] * uz[c];
            (rho * e, 0.5 * rho * u2)
        };
        // Outflow faces: x_high, y_high, z_low, z_high.
        if !done || steps == 0 {
            let dt = solver.stable_dt()?.min(t_end - solver.time());
            // Signed: an outflow face whose neighbour flows inwards feeds
            // the domain (zero-gradient ghost), counted negative.
            let mut face = |c: usize, un: f64, area: f64| {
                let mut flux = 0.0;
                let mut fp = 0.0;
                let mut fm = 0.0;
                let mut th_f = 0.0;
                for r in 0..3 {
                    let (ei, ek) = e_of(r, c);
                    let chem = if r == 0 { rh[0][c] * q } else { 0.0 };
                    flux += (ei + ek + chem) * un;
                    if r == 1 {
                        fp += (ei + ek) * un;
                    }
                    fm += rh[r][c] * un;
                    th_f += th[r][c];
                }
                flux += p[c] * th_f * un;
                fluid_out[0] += flux * area * dt;
                fluid_out[1] += (fp + p[c] * th[1][c] * un) * area * dt;
                fluid_out[2] += fm * area * dt;
            };
            for k in 0..nc[2] {
                for j in 0..nc[1] {
                    let c = idx(nc[0] - 1, j, k);
                    face(c, ux[c], hx[1] * hx[2]);
                }
                for i in 0..nc[0] {
                    let c = idx(i, nc[1] - 1, k);
                    face(c, uy[c], hx[0] * hx[2]);
                }
            }
            for j in 0..nc[1] {
                for i in 0..nc[0] {
                    let c = idx(i, j, 0);
                    face(c, -uz[c], hx[0] * hx[1]);
                    let c = idx(i, j, nc[2] - 1);
                    face(c, uz[c], hx[0] * hx[1]);
                }
            }
        }
        // Detonation arrival on the axis.
        for a in arrivals.iter_mut() {
            let k = ((a.0 - g.lower[2]) / hx[2]) as usize;
            let c = idx(0, 0, k);
            a.2 = a.2.max(p[c]);
            if a.1.is_none() && th[1][c] > 0.5 {
                a.1 = Some(solver.time());
            }
        }
        if steps.is_multiple_of(every) || done {
            let tot = solver.conservation_totals();
            let ice_t = solver.ice().conservation_totals();
            let resc = solver.rescaled_totals();
            let mpm_t = solver.mpm().conservation_totals();
            let ps = solver.mpm().particles();
            let (mut ck, mut ckr, mut ci) = (0.0, 0.0, 0.0);
            let (mut sk, mut sm) = (0.0, 0.0);
            for i in 0..ps.len() {
                let (x, v, m) = (ps.position[i], ps.velocity[i], ps.mass[i]);
                let r = x[0].hypot(x[1]);
                let vr = (x[0] * v[0] + x[1] * v[1]) / r;
                ck += 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
                ckr += 0.5 * m * vr * vr;
                ci += m * ps.specific_internal_energy[i];
                if (x[2] - zg).abs() < hx[2] {
                    sk += 0.5 * m * vr * vr;
                    sm += m;
                }
            }
            let cu_out = mpm_t.energy - ck - ci;
            let mut m = [0.0; 3];
            let (mut pr_int, mut pr_kin, mut air_int, mut air_kin, mut excess) =
                (0.0, 0.0, 0.0, 0.0, 0.0);
            // slice
            let (mut s_mass, mut s_vol, mut s_kin, mut s_exc) = (0.0, 0.0, 0.0, 0.0);
            let mut p_wall = (0.0, 0.0);
            for k in 0..nc[2] {
                let zc = g.lower[2] + (k as f64 + 0.5) * hx[2];
                let in_slice = (zc - zg).abs() < hx[2];
                for j in 0..nc[1] {
                    for i in 0..nc[0] {
                        let c = idx(i, j, k);
                        for r in 0..3 {
                            m[r] += rh[r][c] * vol;
                        }
                        let (ei, ek) = e_of(1, c);
                        pr_int += ei * vol;
                        pr_kin += ek * vol;
                        let (ai, ak) = e_of(2, c);
                        air_int += (ai - rh[2][c] * air_e0(1.1766)) * vol;
                        air_kin += ak * vol;
                        if rh[1][c] > 0.0 && th[1][c] > 1e-3 {
                            let micro = rh[1][c] / th[1][c];
                            let ex = ei - rh[1][c] * e_s(rho0 / micro);
                            excess += ex * vol;
                            if in_slice {
                                s_mass += rh[1][c] * vol;
                                s_vol += th[1][c] * vol;
                                s_kin += ek * vol;
                                s_exc += ex * vol;
                                // pressure in the products beside the copper
                                if th[3][c] > 0.05 {
                                    p_wall.0 += p[c] * th[1][c];
                                    p_wall.1 += th[1][c];
                                }
                            }
                        }
                    }
                }
            }
            let len = 2.0 * hx[2];
            let v_pr = if s_mass > 0.0 {
                rho0 * s_vol / s_mass
            } else {
                f64::NAN
            };
            // inner radius from the slice's copper: mean radius of the particles
            let (mut rsum, mut rmin, mut rn) = (0.0, f64::MAX, 0);
            for i in 0..ps.len() {
                let x = ps.position[i];
                if (x[2] - zg).abs() < hx[2] {
                    let r = x[0].hypot(x[1]);
                    rsum += r;
                    rmin = rmin.min(r);
                    rn += 1;
                }
            }
            let rmean = rsum / rn.max(1) as f64;
            // mean radius of an incompressible shell area A: r_in from r_mean
            let area = r_out * r_out - r_in * r_in;
            let rin_est = (rmean * rmean - 0.5 * area).max(0.0).sqrt();
            let v_geo = (rin_est / r_in).powi(2);
            let eg = |v: f64| -> f64 {
                if v > cj.relative_volume {
                    e0 - e_s(v)
                } else {
                    f64::NAN
                }
            };
            let burnt = 1.0 - m[0] * q / chem0;
            println!(
                "{:.3},{:.5e},{:.5e},{:.5e},{:.5e},{:.5e},{:.5e},{:.5e},{:.5e},{:.4e},{:.4e},{:.4e},{:.5e},{:.5e},{:.5e},{:.5e},{:.5e},{:.4} | {:.3},{:.3e},{:.3},{:.4e},{:.4e},{:.4e},{:.4e},{:.3},{:.2}",
                solver.time() * 1e6,
                ck,
                ckr,
                ci,
                cu_out,
                ice_t.energy,
                resc.energy,
                fluid_out[0],
                tot.energy + fluid_out[0] - e_start,
                m[0],
                m[1],
                m[2],
                pr_int,
                pr_kin,
                air_int,
                air_kin,
                excess,
                burnt,
                v_pr,
                p_wall.0 / p_wall.1.max(1e-300),
                s_mass / len / charge_per_len,
                sk / len,
                s_kin / len,
                s_exc / len,
                eg(v_geo) * charge_per_len,
                (sk / len + s_kin / len) / (eg(v_geo) * charge_per_len),
                rin_est * 1e3,
            );
            let _ = sm;
            if profile {
                let mut cu_z = vec![0.0; nc[2]];
                for i in 0..ps.len() {
                    let (x, v, m) = (ps.position[i], ps.velocity[i], ps.mass[i]);
                    let r = x[0].hypot(x[1]);
                    let vr = (x[0] * v[0] + x[1] * v[1]) / r;
                    let k = ((x[2] - g.lower[2]) / hx[2]).floor();
                    if k >= 0.0 && (k as usize) < nc[2] {
                        cu_z[k as usize] += 0.5 * m * vr * vr;
                    }
                }
                println!("profile t = {:.3} us: z_mm,m_qm/len,m_pr/len,pr_int/len,pr_excess/len,pr_kin/len,cu_kin_r/len,p_axis,T_qm_axis,V_pr_axis,exc_pr_axis(J/kg),min_T_qm,min_T_pr,min_T_air", solver.time() * 1e6);
                {
                    let k = ((zg - g.lower[2]) / hx[2]) as usize;
                    println!("radial (j = 0, k = {k}): x_mm,th_qm,th_pr,th_air,th_cu,rho_pr,T_pr,T_air,p,ux,m_pr_cell");
                    for i in 0..nc[0] {
                        let c = idx(i, 0, k);
                        println!(
                            "  {:.1},{:.3e},{:.3e},{:.3e},{:.3e},{:.4e},{:.4e},{:.4e},{:.4e},{:.1},{:.3e}",
                            (g.lower[0] + (i as f64 + 0.5) * hx[0]) * 1e3,
                            th[0][c],
                            th[1][c],
                            th[2][c],
                            th[3][c],
                            if th[1][c] > 0.0 { rh[1][c] / th[1][c] } else { f64::NAN },
                            tt[1][c],
                            tt[2][c],
                            p[c],
                            ux[c],
                            rh[1][c] * vol
                        );
                    }
                }
                for (k, cu_k) in cu_z.iter().enumerate() {
                    let (mut mq, mut mp, mut pi, mut pe, mut pk) = (0.0, 0.0, 0.0, 0.0, 0.0);
                    let (mut tq, mut tp, mut ta) = (f64::MAX, f64::MAX, f64::MAX);
                    for j in 0..nc[1] {
                        for i in 0..nc[0] {
                            let c = idx(i, j, k);
                            mq += rh[0][c] * vol;
                            mp += rh[1][c] * vol;
                            let (ei, ek) = e_of(1, c);
                            pi += ei * vol;
                            pk += ek * vol;
                            if rh[1][c] > 0.0 && th[1][c] > 1e-3 {
                                pe += (ei - rh[1][c] * e_s(rho0 * th[1][c] / rh[1][c])) * vol;
                            }
                            if th[0][c] > 1e-9 {
                                tq = tq.min(tt[0][c]);
                            }
                            if th[1][c] > 1e-9 {
                                tp = tp.min(tt[1][c]);
                            }
                            if th[2][c] > 1e-9 {
                                ta = ta.min(tt[2][c]);
                            }
                        }
                    }
                    let c = idx(0, 0, k);
                    let vpa = if th[1][c] > 1e-3 {
                        rho0 * th[1][c] / rh[1][c]
                    } else {
                        f64::NAN
                    };
                    let (ei, _) = e_of(1, c);
                    let exa = if th[1][c] > 1e-3 {
                        ei / rh[1][c] - e_s(vpa)
                    } else {
                        f64::NAN
                    };
                    println!(
                        "  {:.1},{:.4e},{:.4e},{:.4e},{:.4e},{:.4e},{:.4e},{:.3e},{:.1},{:.3},{:.3e},{:.1},{:.1},{:.1}",
                        (g.lower[2] + (k as f64 + 0.5) * hx[2]) * 1e3,
                        mq / hx[2],
                        mp / hx[2],
                        pi / hx[2],
                        pe / hx[2],
                        pk / hx[2],
                        cu_k / hx[2],
                        p[c],
                        tt[0][c],
                        vpa,
                        exa,
                        tq,
                        tp,
                        ta
                    );
                }
            }
        }
        if done {
            break;
        }
        let dt = solver.stable_dt()?.min(t_end - solver.time());
        solver.advance(dt).map_err(|e| anyhow!("{e}"))?;
        steps += 1;
    }
    println!(
        "audit: {steps} steps in {:.0} s; fluid outflow: energy {:.5e} J (products {:.5e}), mass {:.5e} kg",
        start.elapsed().as_secs_f64(),
        fluid_out[0],
        fluid_out[1],
        fluid_out[2]
    );
    for a in &arrivals {
        println!(
            "audit: axis z = {:.1} cm: products > 1/2 at {:?} us, peak pressure {:.3e} Pa",
            a.0 * 100.0,
            a.1.map(|t| t * 1e6),
            a.2
        );
    }
    Err(anyhow!("cylinder audit done (report not written)"))
}
