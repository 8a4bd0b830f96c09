//! Where around the E-PD-FRAG tube the cubic lattice makes the wall weak,
//! and where the case breaks: `cargo run --release -p brisance-validation
//! --example pd_frag_angles -- printed|weibull|perturbed SPACING_M [run] [KEY=VALUE
//! ...]` (docs/physics/pd/validation.md, "The strips follow the lattice").
//!
//! For a radial cut at angle θ through the wall (a half-plane holding the
//! axis), the steel bonds that cross it carry, once all of them have
//! yielded (micro-plastic bonds hold a force capped at the same yield
//! stretch), a hoop force proportional to L(θ) = Σ |n·e_θ| over the
//! crossing bonds, n the bond's direction. A perfectly plastic ring under
//! expansion necks where its section's limit load is least, so the lattice
//! decides where the strain gathers if L varies around the tube. Printed:
//! L's spread, its lowest local minima, and with `run` the gaps between the
//! fragments that the mid-length plane cuts, with L's rank at each gap.

use std::f64::consts::PI;

use brisance_validation::pd_fragmentation::{fragment_tube, study_args};
use brisance_validation::pd_tube::Tube;

/// Angular samples of L(θ) around the tube.
const SAMPLES: usize = 2880;

fn angle(p: &[f64; 4]) -> f64 {
    let a = p[1].atan2(p[0]);
    if a < 0.0 {
        a + 2.0 * PI
    } else {
        a
    }
}

/// L(θ) at `SAMPLES` angles: Σ |n·e_θ| over the case bonds crossing the
/// radial half-plane at θ (each bond once).
fn limit_load(reference: &[[f64; 4]], case: &[bool], families: &brisance_pd::Families) -> Vec<f64> {
    let mut l = vec![0.0; SAMPLES];
    let d = 2.0 * PI / SAMPLES as f64;
    for i in 0..reference.len() {
        if !case[i] {
            continue;
        }
        let (pi, ai) = (reference[i], angle(&reference[i]));
        for k in families.row(i) {
            let j = families.neighbours[k] as usize;
            if j <= i || !case[j] {
                continue;
            }
            let pj = reference[j];
            let aj = angle(&pj);
            // The shorter arc from ai to aj.
            let mut da = aj - ai;
            if da > PI {
                da -= 2.0 * PI;
            } else if da < -PI {
                da += 2.0 * PI;
            }
            let (start, span) = if da >= 0.0 { (ai, da) } else { (aj, -da) };
            let xi = [pj[0] - pi[0], pj[1] - pi[1], pj[2] - pi[2]];
            let len = (xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2]).sqrt();
            // Samples θ_m = (m + ½) d strictly inside the arc.
            let m0 = ((start / d) - 0.5).ceil() as i64;
            let m1 = (((start + span) / d) - 0.5).floor() as i64;
            for m in m0..=m1 {
                let theta = (m as f64 + 0.5) * d;
                if theta <= start || theta >= start + span {
                    continue;
                }
                let e = [-theta.sin(), theta.cos(), 0.0];
                let c = (xi[0] * e[0] + xi[1] * e[1]) / len;
                l[m.rem_euclid(SAMPLES as i64) as usize] += c.abs();
            }
        }
    }
    l
}

fn main() {
    let (strength, spacing, mut rest) = match study_args(
        std::env::args().skip(1),
        "pd_frag_angles printed|weibull|perturbed SPACING_M [run] [KEY=VALUE ...]",
    ) {
        Ok(a) => a,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let run = rest.first().map(String::as_str) == Some("run");
    if run {
        rest.remove(0);
    }
    let (file, text) = strength.config();
    let tube = match Tube::at_with(file, text, spacing, &rest) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    };
    let s = &tube.solver;
    let case_id = brisance_pd::cases::case_material(s);
    let case: Vec<bool> = s.materials().iter().map(|&m| m == case_id).collect();
    let l = limit_load(s.reference(), &case, s.families());
    let mean = l.iter().sum::<f64>() / SAMPLES as f64;
    let (lo, hi) = l
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    println!(
        "{strength:?} h = {spacing:e} m: L(θ) over {SAMPLES} angles: min {:.3}, max {:.3} of the mean",
        lo / mean,
        hi / mean
    );
    // Local minima (lower than the 8 samples each side), lowest first.
    let w = 8;
    let mut minima: Vec<(f64, f64)> = (0..SAMPLES)
        .filter(|&m| {
            (1..=w).all(|k| l[m] <= l[(m + k) % SAMPLES] && l[m] <= l[(m + SAMPLES - k) % SAMPLES])
        })
        .map(|m| ((m as f64 + 0.5) * 360.0 / SAMPLES as f64, l[m] / mean))
        .collect();
    minima.sort_by(|a, b| a.1.total_cmp(&b.1));
    let shown: Vec<String> = minima
        .iter()
        .take(24)
        .map(|(a, v)| format!("{a:.1}°:{v:.3}"))
        .collect();
    println!("lowest local minima (angle: L / mean): {}", shown.join(" "));
    if !run {
        return;
    }
    let wall = tube.wall;
    // The tube built above, run (not built again).
    let r = match fragment_tube(tube) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    };
    let s = &r.solver;
    let labels = s.fragment_labels();
    let mid = 0.5 * wall.length;
    // Mid-length case nodes by reference angle, with their fragment.
    let mut ring: Vec<(f64, usize)> = (0..s.node_count())
        .filter(|&i| {
            case[i] && labels[i] != usize::MAX && (s.reference()[i][2] - mid).abs() <= 0.5 * spacing
        })
        .map(|i| (angle(&s.reference()[i]), labels[i]))
        .collect();
    ring.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Gaps: consecutive angles whose fragments differ, both fragments
    // holding at least 3 of the ring's nodes (single-node debris skipped).
    let mut count = std::collections::BTreeMap::new();
    for &(_, f) in &ring {
        *count.entry(f).or_insert(0usize) += 1;
    }
    let big: Vec<(f64, usize)> = ring
        .iter()
        .copied()
        .filter(|&(_, f)| count[&f] >= 3)
        .collect();
    let mut sorted_l = l.clone();
    sorted_l.sort_by(f64::total_cmp);
    let mut gaps = Vec::new();
    for k in 0..big.len() {
        let (a, f) = big[k];
        let (b, g) = big[(k + 1) % big.len()];
        if f != g {
            let mut c = 0.5 * (a + b);
            if b < a {
                c = (0.5 * (a + b + 2.0 * PI)) % (2.0 * PI);
            }
            // L's lowest value within ±one spacing of arc at mid-radius.
            let half = spacing / (0.5 * (wall.inner_radius + wall.outer_radius));
            let m0 = ((c - half) / (2.0 * PI) * SAMPLES as f64).floor() as i64;
            let m1 = ((c + half) / (2.0 * PI) * SAMPLES as f64).ceil() as i64;
            let near = (m0..=m1)
                .map(|m| l[m.rem_euclid(SAMPLES as i64) as usize])
                .fold(f64::INFINITY, f64::min);
            let rank = sorted_l.partition_point(|&v| v < near) as f64 / SAMPLES as f64;
            gaps.push(format!(
                "{:.1}°:{:.3}({:.0}%)",
                c.to_degrees(),
                near / mean,
                100.0 * rank
            ));
        }
    }
    println!(
        "{} fragments of >= 3 ring nodes across mid-length; gaps (angle: lowest L / mean within a spacing, its percentile): {}",
        count.values().filter(|&&n| n >= 3).count(),
        gaps.join(" ")
    );
}
