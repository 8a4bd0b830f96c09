//! E-BLAST2D's gauge 2 and the MPM particles around it
//! (docs/physics/couple/bridge.md, "What makes gauge 2's second hump"):
//! steps `configs/blast2d.ron` in-process and prints both gauges
//! (2 in the MPM region, 1 in the FDM region) about every 0.05 µs from
//! `--from`, beside the 1D reference at the gauges' radius
//! (`blast2d::reference_1d`, 3200 cells), and at `--from`, then every `--every` seconds, the MPM
//! particles whose centre lies in the row of gauge 2's cell (y in
//! [250, 252) mm) and between `--x-from` and `--x-to` (m), sorted by x:
//! position, mass over an initial air particle's, density, pressure,
//! velocity along x, specific internal energy and material (0 air, 1
//! products). `--set KEY=VALUE` (or a bare `KEY=VALUE`) overrides the
//! config as `brisance run --set` does.
//!
//! `cargo run --release -p brisance-validation --example bridge_gauge2_particles -- --from 6.2e-6 --to 8.2e-6 --every 2e-7 --x-from 0.116 --x-to 0.130`
//!
//! Particles that took a deposit or were made by the transport
//! (docs/physics/couple/bridge.md, "Transport") weigh more than an
//! initial particle; those that started in the MPM region weigh 1.

use brisance_compose::build::build_solver;
use brisance_compose::load_file;
use brisance_validation::blast2d::reference_1d;
use std::path::Path;

struct Args {
    from: f64,
    to: f64,
    every: f64,
    x: (f64, f64),
    sets: Vec<String>,
}

fn parse() -> Result<Args, String> {
    let mut a = Args {
        from: 6.2e-6,
        to: 8.2e-6,
        every: 2e-7,
        x: (0.116, 0.130),
        sets: Vec::new(),
    };
    let mut it = std::env::args().skip(1);
    while let Some(k) = it.next() {
        let mut value = |name: &str| -> Result<f64, String> {
            let v = it.next().ok_or(format!("{name} needs a value"))?;
            v.parse().map_err(|e| format!("{name} {v}: {e}"))
        };
        match k.as_str() {
            "--from" => a.from = value("--from")?,
            "--to" => a.to = value("--to")?,
            "--every" => a.every = value("--every")?,
            "--x-from" => a.x.0 = value("--x-from")?,
            "--x-to" => a.x.1 = value("--x-to")?,
            "--set" => a.sets.push(it.next().ok_or("--set needs a value")?),
            _ => a.sets.push(k),
        }
    }
    if !(a.every > 0.0) {
        return Err("--every must be positive".into());
    }
    Ok(a)
}

fn fail(e: impl std::fmt::Display) -> ! {
    eprintln!("bridge_gauge2_particles: {e}");
    std::process::exit(2)
}

fn main() {
    let args = parse().unwrap_or_else(|e| fail(e));
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let loaded =
        load_file(&root.join("configs/blast2d.ron"), &args.sets).unwrap_or_else(|e| fail(e));
    let d = &loaded.scenario.domain;
    let h: [f64; 3] = std::array::from_fn(|k| (d.upper[k] - d.lower[k]) / d.cells[k] as f64);
    // The initial air particles: 2 per cell and direction in (x, y).
    let m0 = 1.225 * h[0] * h[1] * h[2] / 4.0;
    let reference = reference_1d(3200).unwrap_or_else(|e| fail(e));
    let at = |t: f64| {
        let k = reference.time.partition_point(|&x| x < t);
        match (reference.time.get(k.wrapping_sub(1)), reference.time.get(k)) {
            (Some(&t0), Some(&t1)) if t1 > t0 => {
                let f = (t - t0) / (t1 - t0);
                (1.0 - f) * reference.pressure[k - 1] + f * reference.pressure[k]
            }
            _ => f64::NAN,
        }
    };
    let mut s = build_solver(&loaded.scenario).unwrap_or_else(|e| fail(e));
    let fields = vec!["pressure".to_string()];
    let (mut g1, mut g2) = (Vec::new(), Vec::new());
    let mut next_dump = args.from;
    let mut printed = f64::NEG_INFINITY;
    println!("t (µs) | gauge 2 (MPa) | gauge 1 (MPa) | 1D reference (MPa)");
    while s.time() < args.to {
        let dt = s.stable_dt().unwrap_or_else(|e| fail(e));
        s.advance(dt).unwrap_or_else(|e| fail(e));
        let t = s.time();
        if t >= args.from && t - printed >= 0.05e-6 {
            g1.clear();
            g2.clear();
            s.sample([0.125, 0.25, 0.001], &fields, &mut g2)
                .and_then(|_| s.sample([-0.125, 0.25, 0.001], &fields, &mut g1))
                .unwrap_or_else(|e| fail(e));
            println!(
                "{:.3} | {:.2} | {:.2} | {:.2}",
                t * 1e6,
                g2[0] / 1e6,
                g1[0] / 1e6,
                at(t) / 1e6
            );
            printed = t;
        }
        if t >= next_dump {
            next_dump += args.every;
            dump(&*s, t, args.x, m0);
        }
    }
}

fn dump(s: &dyn brisance_core::Solver, t: f64, (x0, x1): (f64, f64), m0: f64) {
    let Some(d) = s.particle_data() else {
        return;
    };
    let get = |n: &str| {
        d.field(n)
            .unwrap_or_else(|| panic!("no particle field {n}"))
    };
    let (mass, p, rho) = (get("mass"), get("pressure"), get("density"));
    let (vx, e, mat) = (
        get("velocity_x"),
        get("specific_internal_energy"),
        get("material"),
    );
    println!("-- t = {:.3} µs", t * 1e6);
    let mut rows: Vec<usize> = (0..d.positions.len())
        .filter(|&i| {
            let x = d.positions[i];
            (x0..x1).contains(&x[0]) && (0.250..0.252).contains(&x[1])
        })
        .collect();
    rows.sort_by(|&a, &b| d.positions[a][0].total_cmp(&d.positions[b][0]));
    for i in rows {
        println!(
            "x {:8.3} mm  y {:8.3} mm  m/m0 {:7.3}  ρ {:7.2}  p {:6.2} MPa  vx {:6.0}  e {:.3e}  material {}",
            d.positions[i][0] * 1e3,
            d.positions[i][1] * 1e3,
            mass[i] / m0,
            rho[i],
            p[i] / 1e6,
            vx[i],
            e[i],
            mat[i]
        );
    }
}
