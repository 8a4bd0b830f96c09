//! The reactant surfaces of step 4's surface-burning reactions
//! ([`ReactionModel::burns_on_a_surface`], the deflagration of seed 000
//! §4.1.2): after step 2, the surface cells of each such reactant and the
//! surface's area per unit cell volume a/V, from the reactant's volume
//! fraction θ_r over the whole grid
//! ([`brisance_reaction::surface_area_densities`] with the Youngs normal
//! and the deflagration's `surface_area` estimate: for `Column`, the
//! default, the reactant cells with an empty face neighbour, the outermost
//! of each column along the normal; for `ExposedFaces`, every reactant
//! cell with an empty face neighbour; for `Upwind`, every reactant cell
//! holding a drop of the reactant toward the normal's side). A
//! cell holds reactant where θ_r > [`crate::reaction::SURFACE_PRESENT`]
//! (10⁻⁴), so the traces an absent material keeps (10⁻⁶) count as empty.
//! A reactant carried by particles does not hold a cell that another
//! Lagrangian material holds more of: its particles' projection onto the
//! cells (seed 000 eq 18) leaves a tail of it past its face (6 % of a cell
//! with linear weights and two particles a cell), and against a solid
//! container that tail, in the container's first cells, was the surface:
//! the burn made its products inside the container's cells, where they
//! found no volume, and the pressure, and with it the rate, rose to
//! gigapascals within microseconds (docs/physics/reaction/deflagration.md).
//!
//! The burn lights where the surface's temperature reaches the model's
//! ignition temperature (seed 000 §4.1.2: "initiation of the burn depends
//! on reaching a threshold temperature at the surface"). The surface lies
//! between the reactant and what is beside it, usually in the next cell
//! (a hot gas, a hot container wall), so a surface cell's temperature is
//! the hottest of the materials present (θ > `SURFACE_PRESENT`) in it and
//! its face neighbours — as Uintah's `Simple_Burn` takes the hottest
//! temperature around a surface cell.
//!
//! The pass runs on the grid in global cell order, so its result does not
//! depend on the patch split or the thread count; a/V is the same on
//! (r, z) rings as on Cartesian cells (the ring's area and volume both
//! carry 2π r_c).

use brisance_core::{Eos, ReactionModel};
use brisance_reaction::deflagration::CellGrid;
use brisance_reaction::{surface_area_densities, SurfaceArea, SurfaceDetection, SurfaceWork};

use super::cell_steps::reaction_state;
use super::{make_params, IceSolver, NS, TEMP, THETA, VSP};
use crate::reaction::{IceRate, REACTANT_LEFT, SURFACE_PRESENT};

/// How many cells behind a surface cell, along its column, a step's burn
/// may reach ([`IceSolver::carry_surface_burns`]).
const CARRY_DEPTH: usize = 3;

/// A cell behind a surface cell along its column, for the carry of
/// [`IceSolver::carry_surface_burns`].
#[derive(Debug, Clone, Copy, Default)]
struct Behind {
    /// Global cell index.
    cell: usize,
    /// The reactant's volume fraction there.
    theta: f64,
    /// The cell's own a/V (1/m) and surface temperature (K).
    area: f64,
    temperature: f64,
}

/// A surface cell and the reactant behind it along its column.
#[derive(Debug, Clone, Copy, Default)]
struct CarryCell {
    /// Global cell index.
    cell: usize,
    /// a/V (1/m), the surface's temperature (K), the swept share of a full
    /// cell per second dF/dt (1/s, [`ReactionModel::rate`]) and the
    /// reactant's volume fraction in the cell.
    area: f64,
    temperature: f64,
    rate: f64,
    theta: f64,
    behind: [Behind; CARRY_DEPTH],
    depth: usize,
}

/// Work arrays of the surface pass (global order), kept between steps.
#[derive(Debug, Default)]
pub(super) struct SurfacePass {
    /// The reactant's volume fraction per cell.
    phi: Vec<f64>,
    /// a/V per cell, 1/m.
    density: Vec<f64>,
    /// The hottest temperature of the materials present per cell, K.
    hottest: Vec<f64>,
    /// The surface's temperature per cell (the hottest of the cell and its
    /// face neighbours; 0 off the surface), K.
    temperature: Vec<f64>,
    /// This rank's values of a gathered pass (its own cells, global
    /// order), and every rank's in global order.
    mine: Vec<f64>,
    gathered: Vec<f64>,
    work: SurfaceWork,
    /// Per reaction: its surface cells with the reactant behind them.
    carry: Vec<Vec<CarryCell>>,
    /// The patch and the patch-local index of every cell, global order.
    locate: Vec<(usize, usize)>,
    /// The largest (a/V) D max(1, v_p/v_r) over every surface burn's
    /// surface cells, 1/s ([`IceSolver::surface_front_rate`]).
    max_rate: f64,
}

/// A surface-burning reaction's surface in a patch's cells (local
/// storage order; empty for a reaction that does not burn on a surface).
#[derive(Debug, Default, Clone)]
pub(super) struct SurfaceCells {
    /// The surface's area per unit cell volume a/V, 1/m (0 off it).
    pub(super) area: Vec<f64>,
    /// The surface's temperature, K (the hottest of the materials present
    /// in the cell and its face neighbours; only read on the surface).
    pub(super) temperature: Vec<f64>,
}

/// Reaction `k`'s surface in cell `c` of a patch, (a/V, T), when the
/// reaction burns on a surface ([`SurfaceCells`] of the patch's scratch).
#[inline]
pub(super) fn surface_at(surface: &[SurfaceCells], k: usize, c: usize) -> Option<(f64, f64)> {
    surface
        .get(k)
        .filter(|s| !s.area.is_empty())
        .map(|s| (s.area[c], s.temperature[c]))
}

impl<E: Eos> IceSolver<E> {
    /// Finds the surface of every surface-burning reaction's reactant in
    /// the state of step 2 and stores its a/V per cell for step 4
    /// ([`brisance_core::ReactionState::surface_area_density`]); clears it
    /// for the other reactions. Called at the end of step 2, after
    /// [`IceSolver::set_reactions`] and after a restart. The error (a grid
    /// the surface pass cannot use) names what is wrong.
    pub(super) fn find_reaction_surfaces(&mut self) -> Result<(), String> {
        let geometry = self.level.geometry;
        let count = geometry.cell_count();
        let grid = CellGrid {
            n: geometry.cells,
            spacing: geometry.spacing,
        };
        let n_mat = self.eos.len();
        let axisymmetric = self.options.geometry.is_axisymmetric();
        // The patch split is fixed for the solver's life: the map from
        // global order to patch cells is built once, and only where a
        // reaction burns on a surface (not on every step of every run).
        let locate = &mut self.surface_pass.locate;
        if locate.len() != count && self.reactions.iter().any(|r| r.rate.burns_on_a_surface()) {
            locate.clear();
            self.level
                .for_each_cell_in_order(|_, pid, c| locate.push((pid, c)));
        }
        self.surface_pass
            .carry
            .resize_with(self.reactions.len(), Vec::new);
        self.surface_pass.max_rate = 0.0;
        for (k, rx) in self.reactions.iter().enumerate() {
            self.surface_pass.carry[k].clear();
            let surface = rx.rate.burns_on_a_surface();
            let patches = self.scratch.iter_mut().zip(&self.level.patches);
            for ((sc, patch), &owned) in patches.zip(&self.ranks.owned) {
                if sc.surface.len() <= k {
                    sc.surface.resize_with(k + 1, Default::default);
                }
                let len = if surface && owned {
                    patch.allocated_cells()
                } else {
                    0
                };
                sc.surface[k].area.resize(len, 0.0);
                sc.surface[k].temperature.resize(len, 0.0);
            }
            if !surface {
                continue;
            }
            // The reactant's fraction and the hottest temperature of each
            // cell, computed by the cell's owner and gathered into global
            // order on every rank.
            let pass = &mut self.surface_pass;
            pass.mine.clear();
            let f = rx.reactant * NS + THETA;
            let state = &self.state;
            let owned = &self.ranks.owned;
            // The other Lagrangian materials, against which a Lagrangian
            // reactant's projected tail is not the reactant.
            let (lagrangian, reactant) = (&self.lagrangian, rx.reactant);
            let other = |r: usize| r != reactant && lagrangian[reactant] && lagrangian[r];
            self.level.for_each_cell_in_order(|_, pid, c| {
                if !owned[pid] {
                    return;
                }
                let d = &state[pid].data;
                let theta = d[f][c];
                let held = (0..n_mat).any(|r| other(r) && d[r * NS + THETA][c] > theta);
                let hottest = (0..n_mat)
                    .filter(|&r| d[r * NS + THETA][c] > SURFACE_PRESENT)
                    .map(|r| d[r * NS + TEMP][c])
                    .fold(f64::NEG_INFINITY, f64::max);
                pass.mine.extend([if held { 0.0 } else { theta }, hottest]);
            });
            self.ranks.in_global_order(
                pass.locate.iter().map(|&(pid, _)| pid),
                &pass.mine,
                2,
                &mut pass.gathered,
            );
            pass.phi.clear();
            pass.hottest.clear();
            for x in pass.gathered.chunks_exact(2) {
                pass.phi.push(x[0]);
                pass.hottest.push(x[1]);
            }
            pass.density.resize(count, 0.0);
            let particles = self.lagrangian[rx.reactant];
            let method = match &rx.rate {
                IceRate::Deflagration(m) => m.surface_area_for(particles),
                _ => SurfaceArea::default_for(particles),
            };
            surface_area_densities(
                &grid,
                method,
                &SurfaceDetection {
                    present_threshold: SURFACE_PRESENT,
                    outermost_in_column: true,
                    ring_inner_radius: axisymmetric.then_some(geometry.origin[0]),
                    ..SurfaceDetection::default()
                },
                &pass.phi,
                &mut pass.work,
                &mut pass.density,
            )
            .map_err(|e| format!("ice: reactions[{k}]: the reactant's surface: {e}"))?;
            // A surface cell's temperature: the hottest of the cell and its
            // face neighbours inside the grid.
            let cells = geometry.cells;
            let [nx, ny, _] = cells;
            let strides = [1, nx, nx * ny];
            pass.temperature.clear();
            pass.temperature.resize(count, 0.0);
            for i in 0..count {
                if !pass.work.on_surface[i] {
                    continue;
                }
                let g = [i % nx, (i / nx) % ny, i / (nx * ny)];
                let mut t = pass.hottest[i];
                for a in 0..3 {
                    if g[a] > 0 {
                        t = t.max(pass.hottest[i - strides[a]]);
                    }
                    if g[a] + 1 < cells[a] {
                        t = t.max(pass.hottest[i + strides[a]]);
                    }
                }
                pass.temperature[i] = t;
            }
            let (pass, scratch) = (&self.surface_pass, &mut self.scratch);
            for (i, &(pid, c)) in pass.locate.iter().enumerate() {
                if owned[pid] {
                    let out = &mut scratch[pid].surface[k];
                    out.area[c] = pass.density[i];
                    out.temperature[c] = pass.temperature[i];
                }
            }
            // The surface cells' burn rates (dF/dt and the products' over
            // the reactant's specific volume), by each cell's owner.
            let pass = &mut self.surface_pass;
            let params = solver_params!(self);
            pass.mine.clear();
            for i in 0..count {
                let (pid, c) = pass.locate[i];
                if !(pass.density[i] > 0.0) || !owned[pid] {
                    continue;
                }
                let d = &self.state[pid].data;
                // Step 4's state of the cell (at the step's start, Δt 0).
                let state = reaction_state(
                    &params,
                    rx,
                    |f| d[f][c],
                    Some((pass.density[i], pass.temperature[i])),
                    0.0,
                );
                let rate = rx.rate.rate(&state, 0.0);
                // The gas the front makes leaves at about D v_p/v_r: the
                // step's limit takes the faster of the front and that flow.
                let expansion = if rate > 0.0 {
                    (d[rx.product * NS + VSP][c] * state.density).max(1.0)
                } else {
                    0.0
                };
                pass.mine.extend([rate, expansion]);
            }
            let surface_owners = (0..count)
                .filter(|&i| pass.density[i] > 0.0)
                .map(|i| pass.locate[i].0);
            self.ranks
                .in_global_order(surface_owners, &pass.mine, 2, &mut pass.gathered);
            // The reactant behind each burning surface cell along its
            // column, the same list on every rank.
            let spacing = geometry.spacing;
            let mut rates = pass.gathered.chunks_exact(2);
            for i in 0..count {
                if !(pass.density[i] > 0.0) {
                    continue;
                }
                let Some(&[rate, expansion]) = rates.next() else {
                    break;
                };
                if !(rate > 0.0) {
                    continue;
                }
                pass.max_rate = pass.max_rate.max(rate * expansion);
                // The column's axis: the one of largest h_a |n_a|; the
                // reactant lies against the normal.
                let n = [
                    pass.work.normal[0][i],
                    pass.work.normal[1][i],
                    pass.work.normal[2][i],
                ];
                let axis = (0..3)
                    .max_by(|&a, &b| {
                        (spacing[a] * n[a].abs()).total_cmp(&(spacing[b] * n[b].abs()))
                    })
                    .unwrap_or(0);
                let mut g = [i % nx, (i / nx) % ny, i / (nx * ny)];
                let mut cell = CarryCell {
                    cell: i,
                    area: pass.density[i],
                    temperature: pass.temperature[i],
                    rate,
                    theta: pass.phi[i],
                    ..CarryCell::default()
                };
                while cell.depth < CARRY_DEPTH {
                    let next = if n[axis] > 0.0 {
                        g[axis].checked_sub(1)
                    } else {
                        Some(g[axis] + 1).filter(|&x| x < cells[axis])
                    };
                    let Some(x) = next else { break };
                    g[axis] = x;
                    let j = g[0] + g[1] * strides[1] + g[2] * strides[2];
                    if !(pass.phi[j] > SURFACE_PRESENT) {
                        break;
                    }
                    cell.behind[cell.depth] = Behind {
                        cell: j,
                        theta: pass.phi[j],
                        area: pass.density[j],
                        temperature: pass.temperature[j],
                    };
                    cell.depth += 1;
                }
                if cell.depth > 0 {
                    pass.carry[k].push(cell);
                }
            }
        }
        for sc in &mut self.scratch {
            sc.surface.truncate(self.reactions.len());
        }
        Ok(())
    }

    /// The rate of the time step's limit on a burning front, 1/s: the
    /// largest (a/V) D max(1, v_p/v_r) over the surface cells of every
    /// surface burn at the state of the last step 2 ((a/V) D is dF/dt of a
    /// full cell, [`ReactionModel::rate`]; v_p/v_r the product's specific
    /// volume over the reactant's). With Δt = cfl / rate neither the front
    /// nor the gas it makes, which leaves the surface at about D v_p/v_r,
    /// crosses more than `cfl` of a cell's depth along the normal, V/a, in
    /// a step. Far below the acoustic rate (D of metres per second against
    /// sound speeds of kilometres per second), it sets the step of the
    /// implicit pressure solve, whose Δt follows the material velocities:
    /// a burn lit in a state at rest had no limit there.
    pub fn surface_front_rate(&self) -> f64 {
        self.surface_pass.max_rate
    }

    /// Reaction `k`'s burning surface as step 4 last burnt it: its area
    /// Σ (a/V) V (m²; on (r, z) rings the whole ring's) and the
    /// area-weighted mean of the model's front speed dF/dt / (a/V) (m/s;
    /// A pⁿ for the deflagration) at each surface cell's pressure now and
    /// surface temperature. `None` for a reaction that does not burn on a
    /// surface or a surface with no area. On several ranks a collective
    /// call (every rank's burning cells are gathered): every rank calls it.
    pub fn burning_surface(&self, k: usize) -> Option<(f64, f64)> {
        let rx = self.reactions.get(k)?;
        if !rx.rate.burns_on_a_surface() {
            return None;
        }
        let vols = self.volumes();
        let params = solver_params!(self);
        // Each rank's burning cells (global index, area, rate), summed in
        // global order on every rank.
        let owned = &self.ranks.owned;
        let mut mine = Vec::new();
        let mut g = 0;
        self.level.for_each_cell_in_order(|_, pid, c| {
            if let Some((a, t)) = owned[pid]
                .then(|| surface_at(&self.scratch[pid].surface, k, c))
                .flatten()
            {
                if a > 0.0 {
                    let d = &self.state[pid].data;
                    // Step 4's state of the cell at a unit area density.
                    let unit = reaction_state(&params, rx, |f| d[f][c], Some((1.0, t)), 0.0);
                    mine.extend([g as f64, a * vols.cell(g), rx.rate.rate(&unit, 0.0)]);
                }
            }
            g += 1;
        });
        let mut cells: Vec<[f64; 3]> = if self.ranks.several() {
            self.ranks
                .comm
                .all_gather(&mine)
                .iter()
                .flat_map(|list| list.chunks_exact(3).map(|x| [x[0], x[1], x[2]]))
                .collect()
        } else {
            mine.chunks_exact(3).map(|x| [x[0], x[1], x[2]]).collect()
        };
        cells.sort_by(|a, b| a[0].total_cmp(&b[0]));
        let (mut area, mut weighted) = (0.0, 0.0);
        for [_, cell_area, rate] in cells {
            area += cell_area;
            weighted += cell_area * rate;
        }
        (area > 0.0).then(|| (area, weighted / area))
    }

    /// The part of a surface cell's burn over `dt` that its reactant
    /// cannot supply goes on into the cells behind it along its column.
    ///
    /// The front sweeps the share (a/V) D Δt of a full cell in a step
    /// (dF/dt Δt, [`ReactionModel::rate`]). Where the surface cell holds
    /// less reactant than that (a sliver the burn left, or reactant the
    /// flow carried out of the cell behind), the front has passed into the
    /// next cell in: that cell gets the area density that burns the rest
    /// at its own pressure, (a/V) · rest / (dF/dt Δt), and the surface's
    /// temperature, up to three cells deep; the surface cell keeps the
    /// share θ_r / (dF/dt Δt) of its a/V that its reactant burns (the burn
    /// its cap would give), so the summed area stays the front's. Without
    /// it a sliver of 10⁻⁴–10⁻³ of a cell kept being the outermost surface cell while
    /// the cell behind it, where the surface really was, did not burn
    /// (V-BURNRATE at 100 MPa regressed at 16 % of A pⁿ;
    /// docs/physics/reaction/deflagration.md).
    ///
    /// Runs in global order before step 4 (at the start of
    /// [`IceSolver::compute_lagrangian_values`] and of
    /// [`IceSolver::lagrangian_burn_fraction`]) and sets the cells behind
    /// from their own values first, so running it twice with one Δt gives
    /// the same areas.
    pub fn carry_surface_burns(&mut self, dt: f64) {
        let pass = &self.surface_pass;
        let owned = &self.ranks.owned;
        // Every rank holds the whole list and writes the cells of its own
        // patches.
        let cell_of = |g: usize| {
            let (pid, c) = pass.locate[g];
            owned[pid].then_some((pid, c))
        };
        for (k, list) in pass.carry.iter().enumerate() {
            for cell in list {
                if let Some((pid, c)) = cell_of(cell.cell) {
                    self.scratch[pid].surface[k].area[c] = cell.area;
                }
                for b in &cell.behind[..cell.depth] {
                    if let Some((pid, c)) = cell_of(b.cell) {
                        let out = &mut self.scratch[pid].surface[k];
                        out.area[c] = b.area;
                        out.temperature[c] = b.temperature;
                    }
                }
            }
            for cell in list {
                let swept = cell.rate * dt;
                let own = cell.theta * (1.0 - REACTANT_LEFT);
                let mut rest = swept - own;
                if rest > 0.0 {
                    // The surface cell burns what it holds: its share of
                    // the area is own / swept (the burn is the same as the
                    // cap on its reactant gives; the summed area stays the
                    // front's).
                    if let Some((pid, c)) = cell_of(cell.cell) {
                        self.scratch[pid].surface[k].area[c] = cell.area * own / swept;
                    }
                }
                for b in &cell.behind[..cell.depth] {
                    if !(rest > 0.0) {
                        break;
                    }
                    let take = rest.min(b.theta * (1.0 - REACTANT_LEFT));
                    if let Some((pid, c)) = cell_of(b.cell) {
                        let out = &mut self.scratch[pid].surface[k];
                        out.area[c] += cell.area * take / swept;
                        out.temperature[c] = out.temperature[c].max(cell.temperature);
                    }
                    rest -= take;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use brisance_core::Solver;
    use brisance_reaction::SurfaceArea;

    use crate::burn_rate::{burning_slab, BurnRate, BurnSurface};
    use crate::PressureSolve;

    /// a/V per cell along the plane slab's row after one step, with the
    /// deflagration's `surface_area` set to `method`.
    fn areas_after_one_step(method: SurfaceArea) -> Vec<f64> {
        let mut cfg = BurnRate::pbx_9501(1.0e8, BurnSurface::Plane);
        cfg.law.surface_area = Some(method);
        let mut s = burning_slab(&cfg, PressureSolve::Explicit).expect("builds");
        let dt = s.stable_dt().expect("dt");
        s.advance(dt).expect("step");
        let mut out = Vec::new();
        s.level
            .for_each_cell_in_order(|_, pid, c| out.push(s.scratch[pid].surface[0].area[c]));
        out
    }

    #[test]
    fn the_surface_pass_uses_the_deflagrations_area_estimate() {
        // The slab fills cells 0–7; after one step the front cell 7 holds a
        // little less than the full cell 6 behind it. `Column` burns only
        // the outermost cell; `Upwind` gives cell 6 its small drop too,
        // and the two share the face's area 1/h.
        let h = 1.0e-4;
        let column = areas_after_one_step(SurfaceArea::Column);
        let upwind = areas_after_one_step(SurfaceArea::Upwind);
        assert!(column[7] > 0.0 && column[6] == 0.0, "{column:?}");
        assert!(upwind[6] > 0.0 && upwind[6] < 0.1 / h, "{upwind:?}");
        // (a full cell holds 1 − 10⁻⁶ of reactant: the products' trace)
        let total: f64 = upwind.iter().sum();
        assert!((total * h - 1.0).abs() < 2e-6, "{total}");
        assert!((column[7] * h - 1.0).abs() < 1e-12, "{}", column[7]);
    }

    /// A surface burn spread over thread ranks
    /// ([`brisance_grid::comm::InProcess`]): V-BURNRATE's 45° slab of
    /// PBX-9501 at 100 MPa with A × 100, so that the front sweeps about a
    /// quarter of a cell a step and the carry into the cells behind
    /// crosses the patches, on 2 × 2 patches over 2, 3 and 4 ranks. Every
    /// rank ends with the saved state, the burning surface and the front's
    /// rate limit of one rank.
    #[test]
    fn a_surface_burn_spread_over_thread_ranks_gives_the_bits_of_one() {
        use std::sync::Arc;

        use crate::burn_rate::burning_slab_on;
        use crate::IceSolver;
        use brisance_eos::EosModel;
        use brisance_grid::comm::{InProcess, Serial};

        let mut cfg = BurnRate::pbx_9501(1.0e8, BurnSurface::Diagonal);
        cfg.law.a *= 100.0;
        cfg.extent_cells = 6;
        let steps = |s: &mut IceSolver<EosModel>| {
            let mut carried = 0;
            for _ in 0..30 {
                let dt = s.stable_dt().expect("dt");
                s.advance(dt).expect("step");
                carried += s.surface_pass.carry[0].len();
            }
            let surface = s.burning_surface(0).expect("burning");
            (
                s.save_state().expect("state"),
                surface,
                s.surface_front_rate(),
                carried,
            )
        };
        let build =
            |comm| burning_slab_on(comm, &cfg, PressureSolve::Explicit, [2, 2, 1]).expect("builds");
        let one = steps(&mut build(Arc::new(Serial)));
        // The burn is carried into the cells behind the surface.
        assert!(one.3 > 0, "nothing carried");
        // One rank gives the bits of one patch.
        let mut whole = burning_slab_on(Arc::new(Serial), &cfg, PressureSolve::Explicit, [1, 1, 1])
            .expect("builds");
        assert!(steps(&mut whole).0 == one.0);
        for ranks in [2, 3, 4] {
            let runs = InProcess::run(ranks, 2, |comm| steps(&mut build(comm)));
            for (r, run) in runs.into_iter().enumerate() {
                assert!(run.0 == one.0, "state, rank {r} of {ranks}");
                assert_eq!(run.1, one.1, "burning surface, rank {r} of {ranks}");
                assert_eq!(run.2, one.2, "front rate, rank {r} of {ranks}");
                assert_eq!(run.3, one.3, "carried cells, rank {r} of {ranks}");
            }
        }
    }

    /// Splits the `Column` estimate's excess area on the burning 45° front
    /// of V-BURNRATE (A/100, 100 MPa) into the part from having more
    /// surface cells than the digitised plane (each counted at the true
    /// normal's area √2 h²) and the part from the normals, and gives the
    /// share of the area in cells holding under 5 % of reactant. A
    /// diagnostic (about three minutes in release):
    /// `cargo test -p brisance-ice --release -- --ignored --nocapture
    /// the_burning_diagonal_front`.
    #[test]
    #[ignore = "a diagnostic run of minutes; prints its split"]
    fn the_burning_diagonal_fronts_excess_area_split() {
        let cfg = BurnRate::a_over_100(BurnSurface::Diagonal);
        let h = cfg.h;
        let mut s = burning_slab(&cfg, PressureSolve::Explicit).expect("builds");
        let t_end = cfg.regress_cells * h / cfg.law.burn_speed(cfg.pressure, 2500.0);
        let cell_area = std::f64::consts::SQRT_2 * h * h;
        let (mut window, mut cells_part, mut normals_part, mut thin, mut total) =
            (0.0, 0.0, 0.0, 0.0, 0.0);
        let mut outside = 0usize;
        while s.time() < t_end * (1.0 - 1e-12) {
            let dt = s.stable_dt().expect("dt").min(t_end - s.time());
            s.advance(dt).expect("step");
            if s.time() < 0.2 * t_end {
                continue;
            }
            let pass = &s.surface_pass;
            let v = h * h * h;
            let reactant: f64 = pass.phi.iter().sum::<f64>() * v;
            let x = (2.0 * reactant / h).sqrt() / std::f64::consts::SQRT_2;
            let true_area = 2.0 * x * h;
            let (mut area, mut count, mut thin_area) = (0.0, 0usize, 0.0);
            let n = s.level.geometry.cells[0];
            for (i, &a) in pass.density.iter().enumerate() {
                if a > 0.0 {
                    area += a * v;
                    count += 1;
                    if pass.phi[i] < 0.05 {
                        thin_area += a * v;
                    }
                    // a surface cell more than 1.5 cells off the plane
                    // the reactant's volume gives
                    let (ci, cj) = ((i % n) as f64 + 0.5, (i / n) as f64 + 0.5);
                    let off = ((ci + cj) * h / std::f64::consts::SQRT_2 - x) / h;
                    outside += usize::from(off.abs() > 1.5);
                }
            }
            let counted = count as f64 * cell_area;
            cells_part += (counted / true_area - 1.0) * dt;
            normals_part += (area - counted) / true_area * dt;
            thin += thin_area / area * dt;
            total += (area / true_area - 1.0) * dt;
            window += dt;
        }
        eprintln!(
            "45° front, time means: area error {:+.3} % = cells {:+.3} % + normals {:+.3} %; \
             area in cells under 5 % reactant {:.3} %; surface cells more than 1.5 h off the plane \
             (summed over steps) {outside}",
            100.0 * total / window,
            100.0 * cells_part / window,
            100.0 * normals_part / window,
            100.0 * thin / window,
        );
        assert!(window > 0.0);
    }
}
