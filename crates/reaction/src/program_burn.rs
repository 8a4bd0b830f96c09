//! Program burn: the time at which each explosive node detonates (seed 004,
//! "Propagation of Detonation (Program Burn)").
//!
//! The seed computes the times during input processing by a Huygens
//! construction: the nodes whose times are given start the front, every
//! other node starts at a large time, and sweeps over the grid set each
//! node's time to the smallest "neighbour time + distance / D" over the
//! explosive nodes in a spherical neighbourhood, until nothing changes. The
//! fixed point of those sweeps is the shortest-path time over the graph whose
//! edges join explosive nodes closer than the neighbourhood radius, with
//! edge weight |x_i − x_j| / D; [`huygens_detonation_times`] computes it
//! directly with Dijkstra's algorithm (one pass, O(E log N), deterministic).
//! Detonations therefore go around inert obstacles, and explosive that no
//! path of explosive nodes reaches never detonates (its time stays
//! `f64::INFINITY`).
//!
//! Where nothing obstructs the explosive the seed allows a straight-line
//! option: t = min over points (t_p + |x − x_p| / D)
//! ([`straight_line_detonation_times`]).

use serde::{Deserialize, Serialize};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// A detonation point: where and when the explosive is initiated.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DetonationPoint {
    /// Position, m.
    pub position: [f64; 3],
    /// Initiation time, s.
    pub time: f64,
}

/// Why detonation times cannot be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BurnError {
    /// A parameter is out of range; names the field.
    #[error("program burn: `{field}`: {message}")]
    InvalidInput {
        /// The offending field.
        field: &'static str,
        /// What is wrong.
        message: String,
    },
    /// A detonation point has no explosive node within the capture radius.
    #[error("program burn: detonation point {index} at {position:?} m has no explosive node within {radius} m")]
    PointOutsideExplosive {
        /// Index of the point in the input list.
        index: usize,
        /// Its position.
        position: [f64; 3],
        /// The capture radius searched.
        radius: f64,
    },
}

/// Program burn behind the [`ReactionModel`](brisance_core::ReactionModel) trait: a point burns
/// completely once the time has reached its detonation time
/// ([`ReactionState::detonation_time`](brisance_core::ReactionState::detonation_time), from [`huygens_detonation_times`]
/// or [`straight_line_detonation_times`]) and not before; it has no rate.
/// This is seed 004's volume burn (a node's products take the volume-burn
/// state at its detonation time; eqs 20–21), the burn fraction the step
/// function F = H(t − t_det). The PD solver asks it, through the trait,
/// whether each node has burnt.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct ProgramBurn;

impl brisance_core::ReactionModel for ProgramBurn {
    fn name(&self) -> &'static str {
        "ProgramBurn"
    }

    fn rate(&self, _state: &brisance_core::ReactionState, _burn_fraction: f64) -> f64 {
        0.0
    }

    fn advance(&self, state: &brisance_core::ReactionState, burn_fraction: f64, _dt: f64) -> f64 {
        if state.time >= state.detonation_time {
            1.0
        } else {
            burn_fraction.clamp(0.0, 1.0)
        }
    }
}

/// Seed 001's program burn of a 1D charge (§4.1, eq 53) behind the
/// [`ReactionModel`](brisance_core::ReactionModel) trait: a cell lit at
/// its lighting time t_L = distance/D
/// ([`ReactionState::detonation_time`](brisance_core::ReactionState::detonation_time))
/// burns over the time the front takes to cross 1.5 cells,
/// F = min(1, (t − t_L) D/(1.5 h)) for t > t_L and 0 before, its pressure
/// F p_EOS (eq 52). The burn fraction is a function of the time alone, so
/// `advance` ignores the step and never lowers the fraction it is given.
/// `brisance remap` and a scenario's `pipeline.charge` run the 1D
/// detonation with it (`brisance_fdm::detonation`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProgramBurnRamp {
    /// Detonation velocity D, m/s.
    pub detonation_velocity: f64,
    /// Cell size h of the 1D grid, m.
    pub cell_size: f64,
}

impl ProgramBurnRamp {
    /// F at time `t` of a cell lit at `t_light` (eq 53).
    #[inline]
    pub fn fraction(&self, t: f64, t_light: f64) -> f64 {
        if t <= t_light {
            0.0
        } else {
            ((t - t_light) * self.detonation_velocity / (1.5 * self.cell_size)).min(1.0)
        }
    }
}

impl brisance_core::ReactionModel for ProgramBurnRamp {
    fn name(&self) -> &'static str {
        "ProgramBurnRamp"
    }

    /// D/(1.5 h) while the front crosses the cell, 0 before and after.
    fn rate(&self, state: &brisance_core::ReactionState, _burn_fraction: f64) -> f64 {
        let f = self.fraction(state.time, state.detonation_time);
        if f > 0.0 && f < 1.0 {
            self.detonation_velocity / (1.5 * self.cell_size)
        } else {
            0.0
        }
    }

    fn advance(&self, state: &brisance_core::ReactionState, burn_fraction: f64, _dt: f64) -> f64 {
        self.fraction(state.time, state.detonation_time)
            .max(burn_fraction.clamp(0.0, 1.0))
    }
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

fn check_inputs(
    positions: &[[f64; 3]],
    explosive: &[bool],
    points: &[DetonationPoint],
    speed: f64,
) -> Result<(), BurnError> {
    if explosive.len() != positions.len() {
        return Err(BurnError::InvalidInput {
            field: "explosive",
            message: format!("{} flags for {} nodes", explosive.len(), positions.len()),
        });
    }
    if !(speed > 0.0 && speed.is_finite()) {
        return Err(BurnError::InvalidInput {
            field: "detonation_velocity",
            message: format!("must be a finite value > 0 m/s, got {speed}"),
        });
    }
    if points.is_empty() {
        return Err(BurnError::InvalidInput {
            field: "points",
            message: "at least one detonation point is needed".into(),
        });
    }
    for p in points {
        if !(p.time.is_finite() && p.position.iter().all(|x| x.is_finite())) {
            return Err(BurnError::InvalidInput {
                field: "points",
                message: format!("point {p:?} must have a finite position and time"),
            });
        }
    }
    Ok(())
}

/// Detonation times by straight lines from the points:
/// t_i = min_p (t_p + |x_i − x_p| / D) for explosive nodes, `INFINITY` for
/// the others. `speed` is the detonation velocity D, m/s.
pub fn straight_line_detonation_times(
    positions: &[[f64; 3]],
    explosive: &[bool],
    points: &[DetonationPoint],
    speed: f64,
) -> Result<Vec<f64>, BurnError> {
    check_inputs(positions, explosive, points, speed)?;
    Ok(positions
        .iter()
        .zip(explosive)
        .map(|(&x, &e)| {
            if !e {
                return f64::INFINITY;
            }
            points
                .iter()
                .map(|p| p.time + distance(x, p.position) / speed)
                .fold(f64::INFINITY, f64::min)
        })
        .collect())
}

#[derive(PartialEq)]
struct Front {
    time: f64,
    node: u32,
}

impl Eq for Front {}

impl Ord for Front {
    fn cmp(&self, other: &Self) -> Ordering {
        // Min-heap on time, ties broken by node index: deterministic.
        other
            .time
            .total_cmp(&self.time)
            .then_with(|| other.node.cmp(&self.node))
    }
}

impl PartialOrd for Front {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// Detonation times by the Huygens construction over a node graph.
///
/// `offsets`/`neighbours` are the graph in compressed-row form (row i is
/// `neighbours[offsets[i]..offsets[i + 1]]`; typically the peridynamic
/// families, so the neighbourhood is the horizon). Only edges between two
/// explosive nodes carry the front. Each point lights the explosive nodes
/// within `capture_radius` of it at t_p + distance / D (an error if there is
/// none). Nodes the front never reaches keep `f64::INFINITY`.
pub fn huygens_detonation_times(
    positions: &[[f64; 3]],
    offsets: &[u32],
    neighbours: &[u32],
    explosive: &[bool],
    points: &[DetonationPoint],
    speed: f64,
    capture_radius: f64,
) -> Result<Vec<f64>, BurnError> {
    check_inputs(positions, explosive, points, speed)?;
    let n = positions.len();
    if offsets.len() != n + 1 || offsets[n] as usize != neighbours.len() {
        return Err(BurnError::InvalidInput {
            field: "offsets",
            message: format!(
                "need {} row offsets ending at {}, got {} ending at {:?}",
                n + 1,
                neighbours.len(),
                offsets.len(),
                offsets.last()
            ),
        });
    }
    if !(capture_radius > 0.0 && capture_radius.is_finite()) {
        return Err(BurnError::InvalidInput {
            field: "capture_radius",
            message: format!("must be a finite value > 0 m, got {capture_radius}"),
        });
    }
    let mut times = vec![f64::INFINITY; n];
    let mut heap = BinaryHeap::new();
    for (index, p) in points.iter().enumerate() {
        let mut lit = false;
        for i in 0..n {
            if !explosive[i] {
                continue;
            }
            let d = distance(positions[i], p.position);
            if d <= capture_radius {
                lit = true;
                let t = p.time + d / speed;
                if t < times[i] {
                    times[i] = t;
                    heap.push(Front {
                        time: t,
                        node: i as u32,
                    });
                }
            }
        }
        if !lit {
            return Err(BurnError::PointOutsideExplosive {
                index,
                position: p.position,
                radius: capture_radius,
            });
        }
    }
    while let Some(Front { time, node }) = heap.pop() {
        let i = node as usize;
        if time > times[i] {
            continue;
        }
        let row = offsets[i] as usize..offsets[i + 1] as usize;
        for &j in &neighbours[row] {
            let j = j as usize;
            if !explosive[j] {
                continue;
            }
            let t = time + distance(positions[i], positions[j]) / speed;
            if t < times[j] {
                times[j] = t;
                heap.push(Front {
                    time: t,
                    node: j as u32,
                });
            }
        }
    }
    Ok(times)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 1D chain of nodes at x = 0, 1, ..., n−1 m, each joined to the
    /// nodes within `reach` places.
    fn chain(n: usize, reach: usize) -> (Vec<[f64; 3]>, Vec<u32>, Vec<u32>) {
        let positions: Vec<[f64; 3]> = (0..n).map(|i| [i as f64, 0.0, 0.0]).collect();
        let mut offsets = vec![0u32];
        let mut neighbours = Vec::new();
        for i in 0..n {
            for j in i.saturating_sub(reach)..(i + reach + 1).min(n) {
                if j != i {
                    neighbours.push(j as u32);
                }
            }
            offsets.push(neighbours.len() as u32);
        }
        (positions, offsets, neighbours)
    }

    /// Not detonated before its time, fully burnt from it on, whatever the
    /// step; and the trait's contract at any time and schedule.
    /// Seed 001 eq 53 by hand: D = 6930 m/s, h = 1 mm, lit at 10 µs:
    /// 1.5 h/D = 0.21645 µs to burn; at 10.1 µs F = 0.1e-6 · 6930/1.5e-3
    /// = 0.462; the rate D/(1.5 h) = 4.62e6 1/s only while it burns.
    #[test]
    fn the_ramp_is_seed_001_eq_53() {
        use brisance_core::{ReactionModel, ReactionState};
        let m = ProgramBurnRamp {
            detonation_velocity: 6930.0,
            cell_size: 1e-3,
        };
        let at = |time: f64| ReactionState {
            time,
            detonation_time: 1.0e-5,
            surface_area_density: 0.0,
            ..Default::default()
        };
        assert_eq!(m.name(), "ProgramBurnRamp");
        assert_eq!(m.advance(&at(0.9e-5), 0.0, 1e-8), 0.0);
        assert_eq!(m.advance(&at(1.0e-5), 0.0, 1e-8), 0.0);
        assert!((m.advance(&at(1.01e-5), 0.0, 1e-8) - 0.462).abs() < 1e-9);
        assert_eq!(m.advance(&at(1.03e-5), 0.0, 1e-8), 1.0);
        assert!((m.rate(&at(1.01e-5), 0.0) - 4.62e6).abs() < 1e-3);
        assert_eq!(m.rate(&at(1.03e-5), 0.0), 0.0);
        assert_eq!(m.rate(&at(0.9e-5), 0.0), 0.0);
        // It never lowers the fraction it is given.
        assert_eq!(m.advance(&at(1.01e-5), 0.7, 1e-8), 0.7);
    }

    proptest::proptest! {
        /// The `ReactionModel` contract of the ramp at any time, lighting
        /// time (or none), burn fraction and step.
        #[test]
        fn the_ramp_keeps_the_reaction_model_contract(
            t in 0.0f64..1e-4, tl in 0.0f64..1e-4, never in proptest::bool::ANY,
            f in 0.0f64..=1.0, dt in 0.0f64..1e-6, d in 1e3f64..1e4, h in 1e-5f64..1e-2,
        ) {
            let m = ProgramBurnRamp { detonation_velocity: d, cell_size: h };
            let state = brisance_core::ReactionState {
                time: t,
                detonation_time: if never { f64::INFINITY } else { tl },
                surface_area_density: 0.0,
                ..Default::default()
            };
            let r = brisance_core::contracts::check_reaction_model(&m, &state, f, dt);
            proptest::prop_assert!(r.is_ok(), "{:?}", r);
        }
    }

    #[test]
    fn program_burn_is_the_step_function_of_the_detonation_time() {
        use brisance_core::{ReactionModel, ReactionState};
        let at = |time: f64| ReactionState {
            time,
            detonation_time: 2e-6,
            surface_area_density: 0.0,
            ..Default::default()
        };
        assert_eq!(ProgramBurn.name(), "ProgramBurn");
        assert_eq!(ProgramBurn.advance(&at(1.999e-6), 0.0, 1e-7), 0.0);
        assert_eq!(ProgramBurn.advance(&at(2e-6), 0.0, 1e-7), 1.0);
        assert_eq!(ProgramBurn.advance(&at(5e-6), 0.0, 0.0), 1.0);
        let never = ReactionState {
            time: 1.0,
            detonation_time: f64::INFINITY,
            surface_area_density: 0.0,
            ..Default::default()
        };
        assert_eq!(ProgramBurn.advance(&never, 0.0, 1.0), 0.0);
        for t in [0.0, 1e-6, 2e-6, 3e-6] {
            for td in [0.0, 2e-6, f64::INFINITY] {
                let s = ReactionState {
                    time: t,
                    detonation_time: td,
                    surface_area_density: 0.0,
                    ..Default::default()
                };
                for f in [0.0, 0.5, 1.0] {
                    brisance_core::contracts::check_reaction_model(&ProgramBurn, &s, f, 1e-7)
                        .unwrap();
                }
            }
        }
    }

    #[test]
    fn huygens_times_on_a_straight_chain_are_distance_over_speed() {
        let (x, o, nb) = chain(10, 2);
        let ex = vec![true; 10];
        let pts = [DetonationPoint {
            position: [0.0; 3],
            time: 1.0e-6,
        }];
        let t = huygens_detonation_times(&x, &o, &nb, &ex, &pts, 2.0, 0.5).unwrap();
        for (i, ti) in t.iter().enumerate() {
            assert!((ti - (1.0e-6 + i as f64 / 2.0)).abs() < 1e-12, "{i}: {ti}");
        }
    }

    #[test]
    fn an_inert_gap_wider_than_the_neighbourhood_stops_the_detonation() {
        // Nodes 4 and 5 are inert; with reach 2 the front can jump one inert
        // node but not two.
        let (x, o, nb) = chain(10, 2);
        let mut ex = vec![true; 10];
        ex[4] = false;
        ex[5] = false;
        let pts = [DetonationPoint {
            position: [0.0; 3],
            time: 0.0,
        }];
        let t = huygens_detonation_times(&x, &o, &nb, &ex, &pts, 1.0, 0.5).unwrap();
        assert_eq!(t[3], 3.0);
        assert!(t[4].is_infinite() && t[5].is_infinite());
        assert!(t[6..].iter().all(|t| t.is_infinite()), "{t:?}");
        // One inert node is jumped (edge 3 → 5 has length 2).
        ex[5] = true;
        let t = huygens_detonation_times(&x, &o, &nb, &ex, &pts, 1.0, 0.5).unwrap();
        assert_eq!(t[5], 5.0);
        assert!(t[4].is_infinite());
    }

    #[test]
    fn detonation_goes_around_an_obstacle() {
        // A 2D grid 5 × 5 (spacing 1 m) with neighbours within √2; the
        // column x = 2 is inert except at y = 4. From (0, 0) the front must
        // go up and over: node (4, 0) is reached later than the straight
        // line says.
        let n = 5;
        let mut x = Vec::new();
        let mut ex = Vec::new();
        for j in 0..n {
            for i in 0..n {
                x.push([i as f64, j as f64, 0.0]);
                ex.push(!(i == 2 && j < 4));
            }
        }
        let mut offsets = vec![0u32];
        let mut nb = Vec::new();
        for a in 0..x.len() {
            for b in 0..x.len() {
                if a != b && distance(x[a], x[b]) < 1.5 {
                    nb.push(b as u32);
                }
            }
            offsets.push(nb.len() as u32);
        }
        let pts = [DetonationPoint {
            position: [0.0; 3],
            time: 0.0,
        }];
        let t = huygens_detonation_times(&x, &offsets, &nb, &ex, &pts, 1.0, 0.1).unwrap();
        let straight = straight_line_detonation_times(&x, &ex, &pts, 1.0).unwrap();
        let target = 4; // (4, 0)
                        // Shortest path (0,0) → (1,1) → (1,2) → (1,3) → (2,4) → (3,3) → (3,2) → (3,1) → (4,0):
                        // four diagonals of √2 and four unit steps.
        let want = 4.0 + 4.0 * 2f64.sqrt();
        assert!((t[target] - want).abs() < 1e-12, "{}", t[target]);
        assert_eq!(straight[target], 4.0);
        assert!(t[2].is_infinite());
    }

    #[test]
    fn several_points_each_with_its_own_start_time() {
        let (x, o, nb) = chain(11, 1);
        let ex = vec![true; 11];
        let pts = [
            DetonationPoint {
                position: [0.0; 3],
                time: 0.0,
            },
            DetonationPoint {
                position: [10.0, 0.0, 0.0],
                time: 2.0,
            },
        ];
        let t = huygens_detonation_times(&x, &o, &nb, &ex, &pts, 1.0, 0.1).unwrap();
        let s = straight_line_detonation_times(&x, &ex, &pts, 1.0).unwrap();
        // Fronts meet where i = 2 + (10 − i): i = 6.
        assert_eq!(t, s);
        assert_eq!(t[5], 5.0);
        assert_eq!(t[6], 6.0);
        assert_eq!(t[7], 5.0);
    }

    #[test]
    fn bad_input_names_the_field() {
        let (x, o, nb) = chain(3, 1);
        let ex = vec![true; 3];
        let p = [DetonationPoint {
            position: [0.0; 3],
            time: 0.0,
        }];
        let e = huygens_detonation_times(&x, &o, &nb, &ex, &p, -1.0, 0.1).unwrap_err();
        assert!(matches!(
            e,
            BurnError::InvalidInput {
                field: "detonation_velocity",
                ..
            }
        ));
        let far = [DetonationPoint {
            position: [50.0, 0.0, 0.0],
            time: 0.0,
        }];
        let e = huygens_detonation_times(&x, &o, &nb, &ex, &far, 1.0, 0.1).unwrap_err();
        assert!(matches!(
            e,
            BurnError::PointOutsideExplosive { index: 0, .. }
        ));
        assert!(straight_line_detonation_times(&x, &ex, &[], 1.0).is_err());
    }

    proptest::proptest! {
        /// On an unobstructed chain the Huygens time is never earlier than
        /// the straight-line time and equals it (the chain is straight).
        #[test]
        fn huygens_never_beats_the_straight_line(n in 3usize..30, reach in 1usize..4, x0 in 0.0f64..2.0, t0 in 0.0f64..1.0) {
            let (x, o, nb) = chain(n, reach);
            let ex = vec![true; n];
            let p = [DetonationPoint { position: [x0, 0.0, 0.0], time: t0 }];
            let h = huygens_detonation_times(&x, &o, &nb, &ex, &p, 3.0, 2.5).unwrap();
            let s = straight_line_detonation_times(&x, &ex, &p, 3.0).unwrap();
            for i in 0..n {
                proptest::prop_assert!(h[i] >= s[i] - 1e-12);
                proptest::prop_assert!((h[i] - s[i]).abs() < 1e-9, "{} vs {}", h[i], s[i]);
            }
        }
    }
}
