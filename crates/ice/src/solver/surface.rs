//! The reactant surfaces of step 4's surface-burning reactions
//! ([`ReactionModel::burns_on_a_surface`], the deflagration of seed 000
//! §4.1.2): after step 2, the surface cells of each such reactant and the
//! surface's area per unit cell volume a/V, from the reactant's volume
//! fraction θ_r over the whole grid
//! ([`brisance_reaction::surface_area_densities`]: the reactant cells
//! with an empty face neighbour, the outermost of each column along the
//! normal, the Youngs normal, the `Column` area). A
//! cell holds reactant where θ_r > [`crate::reaction::SURFACE_PRESENT`]
//! (10⁻⁴), so the traces an absent material keeps (10⁻⁶) count as empty.
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

use super::{IceSolver, NS, TEMP, THETA};
use crate::reaction::SURFACE_PRESENT;

/// Work arrays of the surface pass (global order), kept between steps.
#[derive(Debug, Default)]
pub(super) struct SurfacePass {
    /// The reactant's volume fraction per cell.
    phi: Vec<f64>,
    /// a/V per cell, 1/m.
    density: Vec<f64>,
    /// The hottest temperature of the materials present per cell, K.
    hottest: Vec<f64>,
    work: SurfaceWork,
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
        for (k, rx) in self.reactions.iter().enumerate() {
            let surface = rx.rate.burns_on_a_surface();
            for (sc, patch) in self.scratch.iter_mut().zip(&self.level.patches) {
                if sc.surface.len() <= k {
                    sc.surface.resize_with(k + 1, Default::default);
                }
                let len = if surface { patch.allocated_cells() } else { 0 };
                sc.surface[k].area.resize(len, 0.0);
                sc.surface[k].temperature.resize(len, 0.0);
            }
            if !surface {
                continue;
            }
            let pass = &mut self.surface_pass;
            pass.phi.clear();
            pass.hottest.clear();
            let f = rx.reactant * NS + THETA;
            let state = &self.state;
            self.level.for_each_cell_in_order(|_, pid, c| {
                let d = &state[pid].data;
                pass.phi.push(d[f][c]);
                let hottest = (0..n_mat)
                    .filter(|&r| d[r * NS + THETA][c] > SURFACE_PRESENT)
                    .map(|r| d[r * NS + TEMP][c])
                    .fold(f64::NEG_INFINITY, f64::max);
                pass.hottest.push(hottest);
            });
            pass.density.resize(count, 0.0);
            surface_area_densities(
                &grid,
                SurfaceArea::Column,
                &SurfaceDetection {
                    present_threshold: SURFACE_PRESENT,
                    outermost_in_column: true,
                    ..SurfaceDetection::default()
                },
                &pass.phi,
                &mut pass.work,
                &mut pass.density,
            )
            .map_err(|e| format!("ice: reactions[{k}]: the reactant's surface: {e}"))?;
            let (pass, scratch) = (&self.surface_pass, &mut self.scratch);
            let cells = geometry.cells;
            let mut i = 0;
            self.level.for_each_cell_in_order(|g, pid, c| {
                let out = &mut scratch[pid].surface[k];
                out.area[c] = pass.density[i];
                out.temperature[c] = if pass.work.on_surface[i] {
                    // The cell and its face neighbours inside the grid.
                    let mut t = pass.hottest[i];
                    let mut stride = 1;
                    for a in 0..3 {
                        if g[a] > 0 {
                            t = t.max(pass.hottest[i - stride]);
                        }
                        if g[a] + 1 < cells[a] {
                            t = t.max(pass.hottest[i + stride]);
                        }
                        stride *= cells[a];
                    }
                    t
                } else {
                    0.0
                };
                i += 1;
            });
        }
        for sc in &mut self.scratch {
            sc.surface.truncate(self.reactions.len());
        }
        Ok(())
    }
}
