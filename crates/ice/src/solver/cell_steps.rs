//! The per-cell kernels of the ICE step: step 2's equilibration of one
//! cell (seed 000 eq 7) with the trace rules, the CFL rate of one cell,
//! and steps 8–11's Lagrangian values of one cell (eqs 23–32). The
//! solver's passes over the patches call them
//! ([`super::IceSolver`]); docs/physics/ice/steps.md.

use super::*;

/// The cold-material rule of steps 2 and 12 (docs/physics/ice/steps.md):
/// `(e, T(ρ, e))` where that temperature is positive, otherwise the energy
/// at the temperature `t_keep` the material is held at, `(e(ρ, t_keep),
/// t_keep)` — at the price of energy conservation in that cell.
pub(super) fn kept_warm<E: Eos>(eos: &E, rho: f64, e: f64, t_keep: f64) -> (f64, f64) {
    let t = eos.temperature(rho, e);
    if t > 0.0 {
        (e, t)
    } else {
        (
            eos.specific_internal_energy_from_temperature(rho, t_keep),
            t_keep,
        )
    }
}

/// Volume share below which a fluid is a trace for [`trace_temperature`].
pub(super) const THERMAL_TRACE: f64 = 1e-4;

/// Share of a cell's mass below which a material is a trace whatever
/// volume it claims ([`trace_temperature`], [`cfl_speed`]): a fluid with
/// almost no mass left in a cell the particles hold can sit at the
/// solid's pressure only by an unbounded specific energy, and its volume
/// fraction is then no measure of its presence (the products in the 0.5 mm
/// r–z cylinder's copper cells: θ = 2·10⁻³ at 10⁻¹⁸ kg/m³ and 10¹⁸ K
/// after 1.3 µs, their sound speed collapsing the step).
pub(super) const MASS_TRACE: f64 = 1e-9;

/// Whether a material of volume fraction `theta` and mass share
/// `mass_share` (its mass over the cell's) is a trace for the time step:
/// θ below [`THERMAL_TRACE`] or a mass share below [`MASS_TRACE`]. NaN is
/// not a trace.
#[inline(always)]
pub(super) fn is_trace(theta: f64, mass_share: f64) -> bool {
    theta < THERMAL_TRACE || mass_share < MASS_TRACE
}

/// Material `r`'s signal speed |u| + c in one direction for the CFL step
/// of [`IceSolver::stable_dt`] (`c` is 0 with the implicit pressure). In a
/// coupled run a material of volume fraction θ below [`THERMAL_TRACE`], or
/// of mass share (its mass over the cell's) below [`MASS_TRACE`], is a
/// trace, and
///
/// - a Lagrangian trace sets no speed. Its cell velocity is eq 18 of
///   seed 000 (the nodes' mass-weighted velocity), and a cell holding a
///   trace of the solid gets it from nodes that hold almost none of the
///   particles' mass — the MPM's light nodes, whose velocity after the
///   internal forces, f/m with m → 0, is not any particle's (−4.4 km/s at
///   r = 24.5 mm in the 1 mm r–z cylinder at 1 µs). The ICE does not
///   transport a Lagrangian material (step 12 leaves it to the particles,
///   whose own CFL step the MPM sets from their velocities and sound
///   speeds);
/// - a fluid trace sets its velocity (step 12 moves it) but not its sound
///   speed. The explicit pressure of eqs 19–21 waves through the mixture,
///   whose compressibility Σ θ_r/(ρ_r c_r²) a trace changes by its share:
///   a fluid trace inside the copper, compressed with it and heated
///   where [`trace_temperature`] does not hold it (the cell not full of
///   particles), reached 2·10⁷ K and 91 km/s in the 1 mm r–z cylinder and
///   held Δt at 2·10⁻⁹ s (docs/physics/couple/ice_mpm.md).
///
/// An uncoupled run takes every material's |u| + c, and a NaN θ counts
/// (NaN stops the run).
#[inline(always)]
pub(super) fn cfl_speed(
    coupled: bool,
    lagrangian: bool,
    theta: f64,
    mass_share: f64,
    u: f64,
    c: f64,
) -> f64 {
    if !(coupled && is_trace(theta, mass_share)) {
        u.abs() + c
    } else if lagrangian {
        0.0
    } else {
        u.abs()
    }
}

/// One cell's CFL rate Σ_d max_r s_r,d / Δx_d of [`IceSolver::stable_dt`]
/// (s from [`cfl_speed`], the mass share over the cell's total mass), and
/// the material with the largest s_r,d / Δx_d (for the diagnostic of a
/// collapsed step). In a coupled run with the explicit pressure, a fluid
/// in a cell with particles that [`trace_temperature`] will hold at the
/// particles' temperature because its volume is its heat's
/// ([`claims_volume_by_heat`], at the cell's last pressure and the
/// particles' mass-weighted temperature) sets its velocity but not its
/// sound speed, as a trace: the Δt is taken after step 12, where such a
/// fluid still carries the volume and the sound speed that the next
/// step 2 takes from it (the products in the 0.5 mm r–z cylinder's copper
/// cells at θ ≈ 10⁻³, a mass share of 6·10⁻⁹, 1.4·10⁶ K and 21 km/s,
/// which held Δt at 4.7·10⁻⁹ s; docs/physics/couple/ice_mpm.md).
#[inline(always)]
pub(super) fn cell_cfl_rate<E: Eos>(
    params: &Params<'_, E>,
    d: &[Vec<f64>],
    c: usize,
    acoustic: f64,
) -> (f64, usize) {
    let n = params.eos.len();
    let mass: f64 = (0..n).map(|r| d[r * NS + RHO][c]).sum();
    let mut held = [false; MAX_MATERIALS];
    if params.coupled && acoustic > 0.0 {
        let (mut m, mut mt) = (0.0, 0.0);
        for r in (0..n).filter(|&r| params.lagrangian[r]) {
            m += d[r * NS + RHO][c];
            mt += d[r * NS + RHO][c] * d[r * NS + TEMP][c];
        }
        if m > 0.0 && mt > 0.0 {
            let total: f64 = (0..n)
                .map(|r| d[r * NS + RHO][c] * d[r * NS + VSP][c])
                .sum();
            let (p, t) = (d[n * NS][c], mt / m);
            for r in (0..n).filter(|&r| !params.lagrangian[r] && total > 0.0) {
                // A trace already sets no sound speed: no density solve.
                let rho = d[r * NS + RHO][c];
                held[r] = !is_trace(d[r * NS + THETA][c], rho / mass)
                    && claims_volume_by_heat(params, r, rho / total, p, t);
            }
        }
    }
    let (mut rate, mut top) = (0.0, (0.0_f64, 0));
    for a in (0..3).filter(|&a| params.active[a]) {
        let mut s = 0.0_f64;
        for r in 0..n {
            let v = cfl_speed(
                params.coupled,
                params.lagrangian[r],
                d[r * NS + THETA][c],
                d[r * NS + RHO][c] / mass,
                d[r * NS + VEL + a][c],
                if held[r] {
                    0.0
                } else {
                    acoustic * d[r * NS + SOUND][c]
                },
            );
            s = s.max(v);
            if !(v / params.spacing[a] <= top.0) {
                top = (v / params.spacing[a], r);
            }
        }
        rate += s / params.spacing[a];
    }
    (rate, top.1)
}

/// In a cell the particles fill (their materials' share of the volume
/// above 1 − [`THERMAL_TRACE`]), a fluid of share below
/// [`THERMAL_TRACE`] takes the particles' mass-weighted temperature
/// (flagged in `thermal`): the trace inside a solid is in the solid's
/// heat bath, as Uintah's heat exchange keeps it. So does, in any cell
/// with particles, a fluid of mass share below [`MASS_TRACE`], and one
/// whose mass would fill less than [`THERMAL_TRACE`] of the volume at the
/// cell's pressure (the last step's) and the particles' temperature: a
/// fluid that claims its volume by its heat alone (the products in the
/// copper cells of the 0.5 mm r–z cylinder at θ = 9·10⁻⁴, a mass share of
/// 3·10⁻⁹ and 2.5·10⁷ K, whose sound speed held Δt at 1.1·10⁻⁹ s;
/// docs/physics/couple/ice_mpm.md). Without this the step
/// ratchets it: the solid's compression heats it in steps 8–11, step 2's
/// rescale gives it back its volume by its mass and not by expanding it,
/// and it reached 10⁶ K, its sound speed collapsing the time step
/// (docs/physics/couple/ice_mpm.md). `rho` are the densities over the
/// materials' total volume.
pub(super) fn trace_temperature<E: Eos>(
    params: &Params<'_, E>,
    vals: &[f64],
    rho: &[f64],
    temp: &mut [f64],
    thermal: &mut [bool; MAX_MATERIALS],
) {
    let n = rho.len();
    let share = |r: usize| rho[r] * vals[r * NS + VSP];
    let (mut solid, mut m, mut mt) = (0.0, 0.0, 0.0);
    for r in (0..n).filter(|&r| params.lagrangian[r]) {
        solid += share(r);
        m += rho[r];
        mt += rho[r] * temp[r];
    }
    if !(m > 0.0 && mt > 0.0) {
        return;
    }
    let full = solid > 1.0 - THERMAL_TRACE;
    let total: f64 = rho.iter().sum();
    let t = mt / m;
    let p = vals[n * NS];
    for r in (0..n).filter(|&r| !params.lagrangian[r]) {
        if (full && share(r) < THERMAL_TRACE)
            || rho[r] < MASS_TRACE * total
            || claims_volume_by_heat(params, r, rho[r], p, t)
        {
            temp[r] = t;
            thermal[r] = true;
        }
    }
}

/// Whether fluid `r`, of density `rho` over the materials' total volume,
/// would fill less than [`THERMAL_TRACE`] of it at the pressure `p` (> 0)
/// and the temperature `t` of the particles in its cell: a fluid whose
/// volume is its heat's ([`trace_temperature`] holds it at `t`;
/// [`cell_cfl_rate`] does not take its sound speed). False where the
/// equation of state gives no density at (p, t).
#[inline]
pub(super) fn claims_volume_by_heat<E: Eos>(
    params: &Params<'_, E>,
    r: usize,
    rho: f64,
    p: f64,
    t: f64,
) -> bool {
    p > 0.0
        && matches!(params.eos[r].density(p, t),
            Ok(rho_eq) if rho_eq > 0.0 && rho / rho_eq < THERMAL_TRACE)
}

/// Step 2 on one cell's state-group values `vals` (n·NS + 1 of them):
/// temperatures from (v_r, e_r), the equilibration pressure, then v_r, θ_r,
/// T_r and c_r at the new pressure with e_r kept (so energy is
/// untouched).
pub(super) fn equilibrate_cell<E: Eos>(
    params: &Params<'_, E>,
    vals: &mut [f64],
) -> Result<(EquilibrationReport, KeptWarmCell), (usize, String)> {
    let n = params.eos.len();
    let mut rho = [0.0; MAX_MATERIALS];
    let mut temp = [0.0; MAX_MATERIALS];
    let mut vsp = [0.0; MAX_MATERIALS];
    let mut theta = [0.0; MAX_MATERIALS];
    let mut thermal_trace = [false; MAX_MATERIALS];
    for r in 0..n {
        let b = r * NS;
        rho[r] = vals[b + RHO];
        temp[r] = params.eos[r].temperature(1.0 / vals[b + VSP], vals[b + ENERGY]);
    }
    if params.coupled {
        // Seed 000 §3.3 step 2: with particles carrying some materials, the
        // materials' total volume Σ M_r v_r need not be the cell's, and the
        // volume fractions are each material's share of that total: the
        // pressures equilibrate at the total material volume, θ_r summing
        // to 1 (the macroscopic densities the solve sees are ρ_r / Σ ρ_s v_s).
        let total: f64 = (0..n).map(|r| rho[r] * vals[r * NS + VSP]).sum();
        if total > 0.0 && total.is_finite() {
            for x in &mut rho[..n] {
                *x /= total;
            }
        }
        // A fluid trace inside a cell the particles fill takes their
        // temperature (trace_temperature).
        trace_temperature(params, vals, &rho[..n], &mut temp[..n], &mut thermal_trace);
    }
    let (p, rep) = if params.options.fixed_energy_equilibration {
        let mut energy = [0.0; MAX_MATERIALS];
        for r in 0..n {
            energy[r] = vals[r * NS + ENERGY];
            vsp[r] = vals[r * NS + VSP];
        }
        crate::equilibration::equilibration_pressure_at_fixed_energy(
            params.eos,
            &rho[..n],
            &energy[..n],
            vals[n * NS],
            &params.options.equilibration,
            &mut vsp[..n],
            &mut theta[..n],
        )
    } else {
        equilibration_pressure(
            params.eos,
            &rho[..n],
            &temp[..n],
            vals[n * NS],
            &params.options.equilibration,
            &mut vsp[..n],
            &mut theta[..n],
        )
    }
    .map_err(|e| (0, e.to_string()))?;
    let mut kept = KeptWarmCell::default();
    for r in 0..n {
        let b = r * NS;
        let rho_micro = 1.0 / vsp[r];
        // A cold trace (a few K, after its own expansion where a solid
        // leaves the cell) compressed at fixed e by the new pressure can
        // fall below its 0 K energy (its cold energy rises). It keeps the
        // temperature the equilibration found its volume at instead — the
        // temperature Uintah's equilibration holds.
        let (e, t_new) = if thermal_trace[r] {
            (
                params.eos[r].specific_internal_energy_from_temperature(rho_micro, temp[r]),
                temp[r],
            )
        } else if temp[r] > 0.0 {
            kept_warm(&params.eos[r], rho_micro, vals[b + ENERGY], temp[r])
        } else {
            let e = vals[b + ENERGY];
            (e, params.eos[r].temperature(rho_micro, e))
        };
        if e != vals[b + ENERGY] {
            kept.fired[r] = true;
            // Per unit mass now; times the material's density below.
            kept.energy_density[r] = e - vals[b + ENERGY];
        }
        vals[b + ENERGY] = e;
        let c = params.eos[r].sound_speed(rho_micro, e);
        if !(c > 0.0 && c.is_finite()) {
            return Err((
                0,
                format!(
                    "material {}: sound speed {c:e} m/s at ρ = {rho_micro:e} kg/m³, e = {e:e} J/kg (p = {p:e} Pa)",
                    r + 1
                ),
            ));
        }
        vals[b + VSP] = vsp[r];
        vals[b + THETA] = theta[r];
        if params.coupled && !params.lagrangian[r] {
            // The fluid's mass becomes the new volume fraction at the new
            // specific volume, ρ_r = θ_r/v_r (Uintah's MPMICE, rho_CC_new =
            // θ ρ_micro): where the particles' projected volume moved by
            // more than the fluid fluxes made room for, the fluid keeps its
            // pressure and gives up (or takes) the mass of the difference,
            // instead of a trace of it being compressed many-fold. The
            // change is booked in the conservation totals of the coupled
            // pipeline (docs/physics/couple/ice_mpm.md).
            vals[b + RHO] = theta[r] / vsp[r];
        }
        vals[b + TEMP] = t_new;
        vals[b + SOUND] = c;
        kept.energy_density[r] *= vals[b + RHO];
    }
    vals[n * NS] = p;
    Ok((rep, kept))
}

/// The volume (per unit cell volume) a material of share θ gains at
/// pressure `p` when the heat exchange takes its temperature from `t0` to
/// `t1`: seed 000 eq 31's θβΔT, the first-order form of
/// θ (v(p, T₁)/v(p, T₀) − 1). The first-order form holds while βΔT is
/// small; a trace the exchange cools from a booster's 19 000 K to a metal's
/// 300 K has βΔT ≈ −1 and the linear term took its volume below zero, so
/// beyond |βΔT| = 0.01 the change is the exact one at constant pressure
/// from the equation of state (−θ < change: the volume stays positive).
/// Where the equation of state has no density at (p, T₀) or (p, T₁) the
/// first-order form stands.
pub(super) fn thermal_volume_change<E: Eos>(
    eos: &E,
    p: f64,
    t0: f64,
    t1: f64,
    theta: f64,
) -> Result<f64, brisance_core::EosError> {
    let beta = eos.thermal_expansivity(p, t1)?;
    let linear = theta * beta * (t1 - t0);
    if (beta * (t1 - t0)).abs() <= 0.01 {
        return Ok(linear);
    }
    match (eos.density(p, t0), eos.density(p, t1)) {
        (Ok(r0), Ok(r1)) if r0 > 0.0 && r1 > 0.0 && r0.is_finite() && r1.is_finite() => {
            Ok(theta * (r0 / r1 - 1.0))
        }
        _ => Ok(linear),
    }
}

#[inline]
pub(super) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// What the pass over the cells gives [`lagrangian_cell`] besides the
/// fields: the cell's pressure p (Pa), the divergence ∇·Σθ*u* (1/s), the
/// face pressures' gradient ∇p* (Pa/m), the face pressure work per unit
/// volume (J/m³, with the total-energy closure) and, under
/// [`SolidExchange::Slip`] in a cell on a particle material's surface,
/// that surface's unit normal.
#[derive(Debug, Clone, Copy)]
pub(super) struct CellInputs {
    pub p: f64,
    pub divergence: f64,
    pub grad: [f64; 3],
    pub pressure_work: Option<f64>,
    pub slip_normal: Option<[f64; 3]>,
}

/// Steps 8–11 on one interior cell: returns, per material, the Lagrangian
/// (ρ, u, e, v), and what the trace hold did to the cell's energy.
///
/// In a coupled run the fluid traces step 2 held at the particles'
/// temperature ([`trace_temperature`], the same test on the same state)
/// stay held through the Lagrangian step: they take no share of the
/// energy closure's residual (the Eulerian materials that are not held
/// take it), and their Lagrangian energy is the one at the particles'
/// temperature and their Lagrangian density. Inside a particle-filled
/// cell every fluid is such a trace, and the closure gave them the cell's
/// whole residual — ±10¹⁹ to 10⁵¹ J/kg in the 2 mm cook-off, which step
/// 12's carried-energy slope then spread to the neighbours
/// (docs/physics/couple/cookoff.md). What the hold adds to the cell's
/// energy (its residual left unplaced where no fluid is free to take it,
/// and the held traces' energy change) is returned per material, booked
/// with step 2's rule in [`IceSolver::kept_warm_totals`].
pub(super) fn lagrangian_cell<E: Eos>(
    params: &Params<'_, E>,
    d: &[Vec<f64>],
    c: usize,
    cell: CellInputs,
    surface: &[super::surface::SurfaceCells],
    dt: f64,
) -> Result<([[f64; NL]; MAX_MATERIALS], KeptWarmCell), String> {
    let CellInputs {
        p,
        divergence,
        grad,
        pressure_work,
        slip_normal,
    } = cell;
    let n = params.eos.len();
    // The cell's state values, gathered once (one double index each).
    let mut sv = [0.0; MAX_MATERIALS * NS + 1];
    for (x, f) in sv.iter_mut().zip(&d[..n * NS + 1]) {
        *x = f[c];
    }
    // The fluid traces step 2 held at the particles' temperature, and
    // that temperature (step 2's test on the state it left).
    let mut held = [false; MAX_MATERIALS];
    let mut held_temp = [0.0; MAX_MATERIALS];
    if params.coupled {
        let total: f64 = (0..n).map(|r| sv[r * NS + RHO] * sv[r * NS + VSP]).sum();
        if total > 0.0 && total.is_finite() {
            let mut share = [0.0; MAX_MATERIALS];
            for r in 0..n {
                share[r] = sv[r * NS + RHO] / total;
                held_temp[r] = sv[r * NS + TEMP];
            }
            trace_temperature(params, &sv, &share[..n], &mut held_temp[..n], &mut held);
        }
    }
    let mut kept = KeptWarmCell::default();
    let mut rho = [0.0; MAX_MATERIALS];
    let mut theta = [0.0; MAX_MATERIALS];
    let mut tk = [0.0; MAX_MATERIALS];
    let mut vel = [[0.0; 3]; MAX_MATERIALS];
    let mut e = [0.0; MAX_MATERIALS];
    let mut tk_sum = 0.0;
    for r in 0..n {
        let b = r * NS;
        rho[r] = sv[b + RHO];
        theta[r] = sv[b + THETA];
        let cs = sv[b + SOUND];
        tk[r] = theta[r] * sv[b + VSP] / (cs * cs);
        tk_sum += tk[r];
    }
    // Shares f_r^θ of the cell's volume change (eq 10), with the bound on
    // a material's compression (lagrangian::volume_shares).
    let p_eq = sv[n * NS];
    let VolumeShares {
        share,
        bounded,
        large,
    } = volume_shares(&tk[..n], tk_sum, &theta[..n], dt, divergence, p, p_eq);
    for r in 0..n {
        let b = r * NS;
        let u = [sv[b + VEL], sv[b + VEL + 1], sv[b + VEL + 2]];
        if params.lagrangian[r] {
            // A material carried by particles: its velocity here is the
            // grid's after the particles' internal and body forces (set by
            // the coupled pipeline), to which the cell adds the pressure
            // gradient −θ_r∇p* (eq 24); its internal energy is the
            // particles' (their stress power), changed here by the exchange
            // only.
            let m = lagrangian_momentum(rho[r], u, theta[r], grad, [0.0; 3], dt);
            vel[r] = m.map(|x| x / rho[r]);
            e[r] = sv[b + ENERGY];
            continue;
        }
        let m = lagrangian_momentum(rho[r], u, theta[r], grad, params.options.gravity, dt);
        vel[r] = m.map(|x| x / rho[r]);
        e[r] = lagrangian_energy(rho[r], sv[b + ENERGY], share[r], p, divergence, dt) / rho[r];
        if let Some(g) = large[r] {
            // A volume change of more than half: the isentropic work of the
            // volume the material actually gains or loses, with its local
            // exponent γ = 1/(κ p_eq) (lagrangian::isentropic_energy_change).
            let v = sv[b + VSP];
            let gamma = theta[r] / (tk[r] * p_eq);
            e[r] = sv[b + ENERGY] + isentropic_energy_change(p_eq, v, g, gamma);
        }
    }
    // The cell's total energy ρ(e + ½|u|²) at the step's start, and the
    // work gravity does over the Lagrangian step: with the face pressure
    // work they make the energy balance the closure below restores.
    let mut energy_start = 0.0;
    let mut gravity_work = 0.0;
    for r in 0..n {
        let b = r * NS;
        let u = [sv[b + VEL], sv[b + VEL + 1], sv[b + VEL + 2]];
        energy_start += rho[r] * (sv[b + ENERGY] + 0.5 * dot(u, u));
        if !params.lagrangian[r] {
            for a in 0..3 {
                gravity_work += dt * rho[r] * params.options.gravity[a] * 0.5 * (u[a] + vel[r][a]);
            }
        }
    }
    // Step 4 (seed 000 eq 1): reaction sources at the start-of-step
    // equilibration pressure, moved exactly from reactant to product with
    // the reactant's Lagrangian momentum and energy and its specific volume
    // (crate::reaction). θ is carried from here on with the moved volume.
    //
    // The volume a material's share of the cell's volume change (eq 31,
    // f_r^θ ∇·Σθ*u*, or its bound) adds or removes belongs to its mass, so
    // the burnt fraction of the reactant takes its part of that change to
    // the product with it: seed 000 step 4 asks that the reactant's volume
    // be "depleted at the same rate as the mass". Left with the reactant, a
    // surface cell burnt to 10⁻⁶ of its reactant in one step kept the whole
    // reactant's compression and went to a negative volume
    // (docs/physics/ice/steps.md).
    let mut mechanical = [0.0; MAX_MATERIALS];
    for r in 0..n {
        mechanical[r] = match bounded[r] {
            Some(dv) => dv,
            None => lagrangian_volume(0.0, share[r], divergence, 0.0, dt),
        };
    }
    let mut heat_released = 0.0;
    if !params.reactions.is_empty() {
        for (k, rx) in params.reactions.iter().enumerate() {
            let (a, b) = (rx.reactant, rx.product);
            if params.lagrangian[a] {
                // Particles carry the reactant: they burn in the coupled
                // pipeline's step 14 at the fraction
                // `IceSolver::lagrangian_burn_fraction` gives, and the
                // product takes what they lose before advection
                // (`IceSolver::add_burnt_particles`).
                continue;
            }
            let at = super::surface::surface_at(surface, k, c);
            let state = reaction_state(params, rx, |i| sv[i], at, dt);
            let burnt = rx
                .rate
                .burnt_density(&state, rho[a], rho[b], dt)
                .min(rho[a] * (1.0 - REACTANT_LEFT));
            if burnt > 0.0 {
                let parcel = |r: usize| Parcel {
                    rho: rho[r],
                    velocity: vel[r],
                    energy: e[r],
                    volume: theta[r],
                };
                let (mut pa, mut pb) = (parcel(a), parcel(b));
                let moved = burnt / rho[a] * mechanical[a];
                mechanical[a] -= moved;
                mechanical[b] += moved;
                transfer_burnt_mass(&mut pa, &mut pb, burnt, rx.heat_of_reaction);
                heat_released += burnt * rx.heat_of_reaction;
                for (r, x) in [(a, pa), (b, pb)] {
                    rho[r] = x.rho;
                    vel[r] = x.velocity;
                    e[r] = x.energy;
                    theta[r] = x.volume;
                }
            }
        }
    }
    let rho_sum: f64 = rho[..n].iter().sum();
    // Step 10: momentum exchange.
    let dissipated = match slip_normal {
        Some(normal) => slip_momentum_exchange(
            &rho[..n],
            &theta[..n],
            params.k,
            &super::slip::with_solid(params, &rho[..n], &theta[..n])[..n],
            normal,
            dt,
            &mut vel[..n],
        ),
        None => momentum_exchange(&rho[..n], &theta[..n], params.k, dt, &mut vel[..n]),
    };
    if let Some(work) = pressure_work {
        // Energy-conserving closure of steps 8–10: the cell's total energy
        // changes by the face pressure work −Δt ∇·(p* Σθ*u*), gravity's
        // work and the reactions' heat; what eqs 24–25, the reactions and
        // the exchange leave of it (the kinetic energy the exchange
        // dissipated included) goes to the internal energy of the Eulerian
        // materials in proportion to their heat content ρ_r c_v,r T_r (one
        // relative temperature change for all), so that a trace takes a
        // trace of it and a removal never drives a material below 0 K
        // while the cell has heat. The balance is taken after the exchange:
        // before it a light trace's velocity −Δt v_r ∇p* can be 10⁵ m/s
        // (v_r of a gas beside a dense phase), and a debit of that kinetic
        // energy by one rule and its return as dissipation by another moved
        // energy between materials — into a Lagrangian solid, which takes
        // no share here, at 10⁹ J/m³ a step at the E-CYLINDER's inner wall
        // (docs/physics/ice/steps.md). Materials carried by particles keep
        // the particles' internal energy; their kinetic energy is in the
        // balance, and so is the flow work of their share of the cell's
        // volume change, booked as theirs.
        let mut heat = [0.0; MAX_MATERIALS];
        let mut heat_sum = 0.0;
        for r in 0..n {
            if params.lagrangian[r] || held[r] {
                continue;
            }
            let b = r * NS;
            let t = sv[b + TEMP];
            heat[r] = rho[r] * params.eos[r].cv(1.0 / sv[b + VSP], t) * t;
            heat_sum += heat[r];
        }
        if !(heat_sum > 0.0 && heat_sum.is_finite()) {
            for r in 0..n {
                heat[r] = if params.lagrangian[r] || held[r] {
                    0.0
                } else {
                    rho[r]
                };
            }
            heat_sum = heat[..n].iter().sum();
        }
        let energy_end: f64 = (0..n)
            .map(|r| rho[r] * (e[r] + 0.5 * dot(vel[r], vel[r])))
            .sum();
        // A Lagrangian material's share of the flow work (eq 25,
        // −Δt f_s^θ p ∇·Σθ*u*) is its particles' business: their stress
        // power already holds the p dV of the solid's volume change. Left
        // in the balance it went to the fluids — a fluid trace inside a
        // copper wall that expands took the wall's whole p dV and cooled
        // below 0 K (docs/physics/ice/steps.md).
        let solid_flow_work: f64 = (0..n)
            .filter(|&r| params.lagrangian[r])
            .map(|r| -dt * share[r] * p * divergence)
            .sum();
        let delta =
            work + gravity_work + heat_released - (energy_end - energy_start) - solid_flow_work;
        if heat_sum > 0.0 && heat_sum.is_finite() {
            for r in 0..n {
                if heat[r] > 0.0 {
                    e[r] += heat[r] / heat_sum * delta / rho[r];
                }
            }
        } else {
            // Every fluid is a held trace: the residual is left unplaced,
            // booked on the held traces by their mass.
            let held_mass: f64 = (0..n).filter(|&r| held[r]).map(|r| rho[r]).sum();
            for r in (0..n).filter(|&r| held[r] && held_mass > 0.0) {
                kept.fired[r] = true;
                kept.energy_density[r] -= rho[r] / held_mass * delta;
            }
        }
    } else if dissipated != 0.0 {
        // Without the closure the dissipated kinetic energy goes back to
        // heat with one specific increment for every material.
        let de = dissipated / rho_sum;
        for x in &mut e[..n] {
            *x += de;
        }
    }
    let mut tbt = [0.0; MAX_MATERIALS];
    if params.heat_active {
        let mut temp = [[0.0; 1]; MAX_MATERIALS];
        let mut rho_cv = [0.0; MAX_MATERIALS];
        let mut cv = [0.0; MAX_MATERIALS];
        for r in 0..n {
            let rho_micro = 1.0 / sv[r * NS + VSP];
            temp[r][0] = params.eos[r].temperature(rho_micro, e[r]);
            // A Lagrangian material whose particles carry a specific heat
            // exchanges with theirs (its energy below changes by the heat
            // c ΔT it takes, which its particles take through their H(T)).
            cv[r] = match params.specific_heat.get(r) {
                Some(Some(c)) => c.at(temp[r][0]),
                _ => params.eos[r].cv(rho_micro, temp[r][0]),
            };
            rho_cv[r] = rho[r] * cv[r];
        }
        let before = temp;
        // A Lagrangian material's trace (no body: the solid's trace state
        // at its reference temperature where its particles are not) takes
        // no part: with θ = 0 in the exchange its row is ΔT = 0 and it
        // neither gives the fluids heat nor takes it from them. Its heat
        // would reach no particle, and a trace at its reference
        // temperature beside a fluid at another was a source of heat
        // without end (docs/physics/couple/ice_mpm.md, "Heat between the
        // frames").
        let mut theta_x = theta;
        let rho_sum: f64 = rho[..n].iter().sum();
        for r in 0..n {
            if params.lagrangian[r] && is_trace(theta[r], rho[r] / rho_sum) {
                theta_x[r] = 0.0;
            }
        }
        heat_exchange(&rho_cv[..n], &theta_x[..n], params.h, dt, &mut temp[..n]);
        for r in 0..n {
            let dtemp = temp[r][0] - before[r][0];
            e[r] += cv[r] * dtemp;
            if dtemp != 0.0 {
                tbt[r] = thermal_volume_change(
                    &params.eos[r],
                    p.max(f64::MIN_POSITIVE),
                    before[r][0],
                    temp[r][0],
                    theta[r],
                )
                .map_err(|err| format!("material {}: thermal expansivity: {err}", r + 1))?
                    / dt;
            }
        }
    }
    let mut out = [[0.0; NL]; MAX_MATERIALS];
    for r in 0..n {
        let f = volume_change_share(tk[r], tk_sum);
        // Eq 31: the mechanical change f_r^θ ∇·Σθ*u* (or its bound), then
        // the exchange's thermal change θ_r β_r Ṫ_r of the material's own
        // volume, taken as the relative change it is (of the volume after
        // the mechanical one: a trace compressed to a few per cent of its
        // volume and cooled by the exchange from 19 000 to 300 K went below
        // zero when its shrink was taken of its volume at the step's
        // start), and the compensation −f_r^θ Σ_s θ_s β_s Ṫ_s. With no
        // heat exchange both thermal terms are zero and this is eq 31 as
        // before, bit for bit.
        let mechanical = theta[r] + mechanical[r];
        let own = if theta[r] > 0.0 {
            dt * tbt[r] / theta[r]
        } else {
            0.0
        };
        let compensation = dt * (thermal_expansion_term(&tbt[..n], r, f) - tbt[r]);
        let theta_l = mechanical * (1.0 + own) + compensation;
        if held[r] && theta_l > 0.0 {
            let e_held = params.eos[r]
                .specific_internal_energy_from_temperature(rho[r] / theta_l, held_temp[r]);
            if e_held.is_finite() && e_held != e[r] {
                kept.fired[r] = true;
                kept.energy_density[r] += rho[r] * (e_held - e[r]);
                e[r] = e_held;
            }
        }
        out[r][L_RHO] = rho[r];
        out[r][L_VEL..L_VEL + 3].copy_from_slice(&vel[r]);
        out[r][L_ENERGY] = e[r];
        out[r][L_VSP] = theta_l / rho[r];
        if params.lagrangian[r] {
            // The particles carry its volume; only the exchange's changes
            // are read back.
            out[r][L_VSP] = sv[r * NS + VSP];
            if !(e[r].is_finite() && vel[r].iter().all(|u| u.is_finite())) {
                return Err(format!(
                    "material {} (particles): specific internal energy {:e} J/kg, velocity {:?} m/s \
                     after the exchange (steps 8–10, p = {p:e} Pa)",
                    r + 1,
                    e[r],
                    vel[r]
                ));
            }
            continue;
        }
        if !(theta_l > 0.0 && e[r].is_finite() && vel[r].iter().all(|u| u.is_finite())) {
            return Err(format!(
                "material {}: Lagrangian volume fraction {theta_l:e}, specific internal energy {:e} J/kg, \
                 velocity ({:e}, {:e}, {:e}) m/s (steps 8–11, p = {p:e} Pa)",
                r + 1,
                e[r],
                vel[r][0],
                vel[r][1],
                vel[r][2]
            ));
        }
    }
    Ok((out, kept))
}

/// The local state step 4 hands reaction `rx`'s rate in a cell whose
/// state values (flat, `NS` per material, the equilibration pressure last)
/// `value` gives: the equilibration pressure, the reactant's density 1/v
/// and the step's end time; the reactant's temperature, or for a surface
/// burn ([`ReactionModel::burns_on_a_surface`]) the surface's temperature
/// and area density (1/m) that step 2's surface pass found in the cell
/// (`surface`: a/V and T; a/V = 0 off the surface).
#[inline]
pub(super) fn reaction_state<E: Eos>(
    params: &Params<'_, E>,
    rx: &IceReaction,
    value: impl Fn(usize) -> f64,
    surface: Option<(f64, f64)>,
    dt: f64,
) -> ReactionState {
    let n = params.eos.len();
    let r = rx.reactant;
    let (temperature, surface_area_density) = match surface {
        Some((area, t)) if rx.rate.burns_on_a_surface() => (t, area),
        _ => (value(r * NS + TEMP), 0.0),
    };
    ReactionState {
        pressure: value(n * NS),
        temperature,
        density: 1.0 / value(r * NS + VSP),
        time: params.time + dt,
        detonation_time: f64::INFINITY,
        surface_area_density,
    }
}
